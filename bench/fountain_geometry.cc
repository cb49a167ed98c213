#include "bench/fountain_geometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace semap::bench {

Eigen::Vector3d InCamera(const PinholeCamera& camera, const Eigen::Vector3d& p_world) {
  return camera.world_from_cam.inverse() * p_world;
}

Eigen::Vector2d ProjectPx(const PinholeCamera& camera, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d q = camera.K * InCamera(camera, p_world);
  return q.head<2>() / q.z();
}

Eigen::Matrix3d FundamentalMatrix(const PinholeCamera& a, const PinholeCamera& b) {
  const Pose3d b_from_a = b.world_from_cam.inverse() * a.world_from_cam;
  const Eigen::Vector3d t = b_from_a.translation();
  Eigen::Matrix3d t_cross;
  t_cross << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
  const Eigen::Matrix3d essential = t_cross * b_from_a.linear();
  return b.K.inverse().transpose() * essential * a.K.inverse();
}

double EpipolarDistancePx(const Eigen::Matrix3d& F, const Eigen::Vector2d& x_a_px,
                          const Eigen::Vector2d& x_b_px) {
  const Eigen::Vector3d line = F * x_a_px.homogeneous();
  const double norm = line.head<2>().norm();
  if (norm == 0.0) return std::numeric_limits<double>::infinity();
  return std::abs(line.dot(x_b_px.homogeneous())) / norm;
}

namespace {

// Union-find over dense indices, with path halving.
class DisjointSets {
 public:
  int Add() {
    parent_.push_back(static_cast<int>(parent_.size()));
    return parent_.back();
  }
  int Find(int i) {
    while (parent_[static_cast<size_t>(i)] != i) {
      int& p = parent_[static_cast<size_t>(i)];
      p = parent_[static_cast<size_t>(p)];
      i = p;
    }
    return i;
  }
  void Join(int i, int j) { parent_[static_cast<size_t>(Find(i))] = Find(j); }

 private:
  std::vector<int> parent_;
};

std::uint64_t Key(const ViewKeypoint& k) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.view)) << 32) |
         static_cast<std::uint32_t>(k.keypoint);
}

}  // namespace

std::vector<std::vector<ViewKeypoint>> BuildTracks(const std::vector<KeypointMatch>& matches, int min_views) {
  DisjointSets sets;
  std::unordered_map<std::uint64_t, int> index;
  std::vector<ViewKeypoint> keypoints;
  auto index_of = [&](const ViewKeypoint& k) {
    auto [it, added] = index.try_emplace(Key(k), 0);
    if (added) {
      it->second = sets.Add();
      keypoints.push_back(k);
    }
    return it->second;
  };
  for (const KeypointMatch& m : matches) {
    if (m.a.view == m.b.view) continue;
    const int a = index_of(m.a);
    const int b = index_of(m.b);
    sets.Join(a, b);
  }
  std::unordered_map<int, std::vector<ViewKeypoint>> by_root;
  for (size_t i = 0; i < keypoints.size(); ++i)
    by_root[sets.Find(static_cast<int>(i))].push_back(keypoints[i]);
  std::vector<std::vector<ViewKeypoint>> tracks;
  for (auto& [root, track] : by_root) {
    if (static_cast<int>(track.size()) < min_views) continue;
    std::sort(track.begin(), track.end(), [](const ViewKeypoint& x, const ViewKeypoint& y) {
      return x.view != y.view ? x.view < y.view : x.keypoint < y.keypoint;
    });
    const bool one_per_view =
        std::adjacent_find(track.begin(), track.end(),
                           [](const auto& x, const auto& y) { return x.view == y.view; }) == track.end();
    if (one_per_view) tracks.push_back(std::move(track));
  }
  // A fixed order whatever the hash map's: by the first keypoint.
  std::sort(tracks.begin(), tracks.end(), [](const auto& x, const auto& y) { return Key(x[0]) < Key(y[0]); });
  return tracks;
}

std::optional<Eigen::Vector3d> TriangulateLinear(const std::vector<Observation>& observations) {
  if (observations.size() < 2) return std::nullopt;
  Eigen::MatrixXd A(2 * observations.size(), 4);
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    const Pose3d cam_from_world = o.camera.world_from_cam.inverse();
    Eigen::Matrix<double, 3, 4> P;
    P << cam_from_world.linear(), cam_from_world.translation();
    const Eigen::Vector3d y = o.camera.K.inverse() * o.uv_px.homogeneous();
    const Eigen::Vector2d n = y.head<2>() / y.z();
    const Eigen::RowVector4d rows[2] = {n.x() * P.row(2) - P.row(0), n.y() * P.row(2) - P.row(1)};
    for (int r = 0; r < 2; ++r) A.row(static_cast<Eigen::Index>(2 * i) + r) = rows[r].normalized();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d h = svd.matrixV().col(3);
  if (std::abs(h.w()) < 1e-12 * h.head<3>().norm()) return std::nullopt;
  return Eigen::Vector3d(h.head<3>() / h.w());
}

Eigen::Vector3d RefineReprojection(const std::vector<Observation>& observations, Eigen::Vector3d p_world,
                                   int iterations) {
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (const Observation& o : observations) {
      const Eigen::Matrix3d K_R = o.camera.K * o.camera.world_from_cam.linear().transpose();
      const Eigen::Vector3d q = o.camera.K * InCamera(o.camera, p_world);
      if (!(q.z() > 0.0)) continue;
      Eigen::Matrix<double, 2, 3> dpx_dq;
      dpx_dq << 1.0 / q.z(), 0.0, -q.x() / (q.z() * q.z()), 0.0, 1.0 / q.z(), -q.y() / (q.z() * q.z());
      const Eigen::Matrix<double, 2, 3> J = dpx_dq * K_R;
      const Eigen::Vector2d residual_px = q.head<2>() / q.z() - o.uv_px;
      normal += J.transpose() * J;
      gradient += J.transpose() * residual_px;
    }
    const Eigen::Vector3d step = normal.ldlt().solve(-gradient);
    if (!step.allFinite()) break;
    p_world += step;
    if (step.norm() < 1e-12 * (1.0 + p_world.norm())) break;
  }
  return p_world;
}

std::vector<double> ReprojectionErrorsPx(const std::vector<Observation>& observations,
                                         const Eigen::Vector3d& p_world) {
  std::vector<double> errors;
  errors.reserve(observations.size());
  for (const Observation& o : observations) {
    const bool in_front = InCamera(o.camera, p_world).z() > 0.0;
    errors.push_back(in_front ? (ProjectPx(o.camera, p_world) - o.uv_px).norm()
                              : std::numeric_limits<double>::infinity());
  }
  return errors;
}

std::optional<Eigen::Vector3d> TriangulateTrack(const std::vector<Observation>& observations,
                                                double max_error_px, int iterations) {
  const std::optional<Eigen::Vector3d> linear = TriangulateLinear(observations);
  if (!linear) return std::nullopt;
  const Eigen::Vector3d p_world = RefineReprojection(observations, *linear, iterations);
  const std::vector<double> errors = ReprojectionErrorsPx(observations, p_world);
  const bool kept = std::all_of(errors.begin(), errors.end(), [&](double e) { return e < max_error_px; });
  if (!kept) return std::nullopt;
  return p_world;
}

}  // namespace semap::bench
