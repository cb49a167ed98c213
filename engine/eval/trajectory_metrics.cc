#include "engine/eval/trajectory_metrics.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

double AngleRad(const Eigen::Matrix3d& r) {
  // Clamped: rounding can push the cosine just past ±1.
  return std::acos(std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0));
}

// Cumulative path length of the truth at each frame.
std::vector<double> Distances(const std::vector<Pose3d>& poses) {
  std::vector<double> d(poses.size(), 0.0);
  for (size_t i = 1; i < poses.size(); ++i) {
    d[i] = d[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return d;
}

// The error of the estimate's motion from frame a to b against the truth's.
Pose3d MotionError(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate, size_t a,
                   size_t b) {
  const Pose3d true_motion = truth[a].inverse() * truth[b];
  const Pose3d est_motion = estimate[a].inverse() * estimate[b];
  return true_motion.inverse() * est_motion;
}

void CheckSameLength(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate) {
  SEMAP_ASSERT(truth.size() == estimate.size(),
               "trajectories of " << truth.size() << " and " << estimate.size() << " poses");
}

}  // namespace

KittiOdometryError KittiOdometryMetric(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                       const KittiOdometryOptions& options) {
  CheckSameLength(truth, estimate);
  SEMAP_ASSERT(options.step_frames >= 1);
  const std::vector<double> dist = Distances(truth);
  KittiOdometryError out;
  double t_sum = 0.0, r_sum = 0.0;
  for (const double length : options.lengths_m) {
    SegmentDrift drift;
    drift.length_m = length;
    double t = 0.0, r = 0.0;
    for (size_t first = 0; first < truth.size(); first += static_cast<size_t>(options.step_frames)) {
      // The first frame at least `length` further along the truth's path.
      const auto it = std::lower_bound(dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(),
                                       dist[first] + length);
      if (it == dist.end()) break;
      const size_t last = static_cast<size_t>(it - dist.begin());
      const Pose3d e = MotionError(truth, estimate, first, last);
      t += e.translation().norm() / length;
      r += AngleRad(e.linear()) / length;
      ++drift.segments;
    }
    if (drift.segments == 0) continue;
    drift.translation_percent = 100.0 * t / drift.segments;
    drift.rotation_deg_per_m = kRadToDeg * r / drift.segments;
    out.per_length.push_back(drift);
    t_sum += t;
    r_sum += r;
    out.overall.segments += drift.segments;
  }
  if (out.overall.segments > 0) {
    out.overall.translation_percent = 100.0 * t_sum / out.overall.segments;
    out.overall.rotation_deg_per_m = kRadToDeg * r_sum / out.overall.segments;
  }
  return out;
}

RelativePoseError RelativeError(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                int delta_frames, double min_length_m) {
  CheckSameLength(truth, estimate);
  SEMAP_ASSERT(delta_frames >= 1);
  const std::vector<double> dist = Distances(truth);
  RelativePoseError out;
  double t_sq = 0.0, r_sq = 0.0, t_rel = 0.0, r_rel = 0.0, length_sum = 0.0;
  const size_t delta = static_cast<size_t>(delta_frames);
  for (size_t a = 0; a + delta < truth.size(); ++a) {
    const size_t b = a + delta;
    const Pose3d e = MotionError(truth, estimate, a, b);
    const double t_err = e.translation().norm();
    const double r_err = AngleRad(e.linear());
    t_sq += t_err * t_err;
    r_sq += r_err * r_err;
    ++out.windows;
    const double length = dist[b] - dist[a];
    if (length < min_length_m) continue;
    t_rel += t_err / length;
    r_rel += r_err / length;
    length_sum += length;
    ++out.drift.segments;
  }
  if (out.windows > 0) {
    out.translation_rmse_m = std::sqrt(t_sq / out.windows);
    out.rotation_rmse_deg = kRadToDeg * std::sqrt(r_sq / out.windows);
  }
  if (out.drift.segments > 0) {
    out.drift.length_m = length_sum / out.drift.segments;
    out.drift.translation_percent = 100.0 * t_rel / out.drift.segments;
    out.drift.rotation_deg_per_m = kRadToDeg * r_rel / out.drift.segments;
  }
  return out;
}

FrameRotationFit FitFrameRotation(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                  int delta_frames, double min_length_m) {
  CheckSameLength(truth, estimate);
  SEMAP_ASSERT(delta_frames >= 1);
  // The pull towards the identity, per window: the pairs (e_k, e_k) of the three axes at this weight. Far
  // below what a window that tells a direction adds; decisive only about an axis that nothing tells.
  constexpr double kIdentityPull = 0.01;
  // A window's rotation of this many radians weighs as much as its translation direction: a turn of a few
  // degrees a frame tells the roll about the direction of travel, the noise of a straight drive does not.
  constexpr double kRotationUnitRad = 0.1;
  const std::vector<double> dist = Distances(truth);
  const size_t delta = static_cast<size_t>(delta_frames);
  // Σ truth · estimateᵀ over the pairs: each window's translation direction, and its rotation vector (rad; a
  // rotation R_truth = R R_estimate Rᵀ turns the axis by R: what tells a roll about the direction of travel
  // in a turn).
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
  int windows = 0;
  for (size_t a = 0; a + delta < truth.size(); ++a) {
    const size_t b = a + delta;
    if (dist[b] - dist[a] < min_length_m) continue;
    const Pose3d truth_motion = truth[a].inverse() * truth[b];
    const Pose3d estimate_motion = estimate[a].inverse() * estimate[b];
    if (truth_motion.translation().norm() == 0.0 || estimate_motion.translation().norm() == 0.0) continue;
    cross += truth_motion.translation().normalized() * estimate_motion.translation().normalized().transpose();
    const Eigen::AngleAxisd truth_rotation(truth_motion.linear()),
        estimate_rotation(estimate_motion.linear());
    cross += (truth_rotation.angle() / kRotationUnitRad * truth_rotation.axis()) *
             (estimate_rotation.angle() / kRotationUnitRad * estimate_rotation.axis()).transpose();
    ++windows;
  }
  cross += kIdentityPull * std::max(windows, 1) * Eigen::Matrix3d::Identity();
  // R maximising Σ truth_dir · R estimate_dir: R = U diag(1, 1, det(U Vᵀ)) Vᵀ for cross = U S Vᵀ.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  FrameRotationFit out;
  out.truth_cam_from_estimate_cam = svd.matrixU() * d * svd.matrixV().transpose();
  const Eigen::AngleAxisd angle_axis(out.truth_cam_from_estimate_cam);
  out.angles_deg = kRadToDeg * angle_axis.angle() * angle_axis.axis();
  // The truth's poses of the estimate's camera frame: world_from_truth_cam · truth_cam_from_estimate_cam.
  Pose3d extrinsic = Pose3d::Identity();
  extrinsic.linear() = out.truth_cam_from_estimate_cam;
  std::vector<Pose3d> truth_in_estimate_frame;
  truth_in_estimate_frame.reserve(truth.size());
  for (const Pose3d& p : truth) truth_in_estimate_frame.push_back(p * extrinsic);
  out.relative = RelativeError(truth_in_estimate_frame, estimate, delta_frames, min_length_m);
  return out;
}

AbsoluteTrajectoryError AbsoluteError(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate) {
  CheckSameLength(truth, estimate);
  AbsoluteTrajectoryError out;
  if (truth.empty()) return out;
  const std::vector<double> dist = Distances(truth);
  out.path_length_m = dist.back();
  const Eigen::Index n = static_cast<Eigen::Index>(truth.size());
  Eigen::Matrix3Xd est(3, n), tru(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    est.col(i) = estimate[static_cast<size_t>(i)].translation();
    tru.col(i) = truth[static_cast<size_t>(i)].translation();
  }
  // With fewer than 3 positions (or all on a line) the rotation is not determined; Umeyama still gives the
  // best one it finds, and the translation makes the centroids meet.
  const Eigen::Matrix4d align = n >= 2 ? Eigen::umeyama(est, tru, false) : Eigen::Matrix4d::Identity();
  double sq = 0.0, sum = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = align.topLeftCorner<3, 3>() * est.col(i) + align.topRightCorner<3, 1>();
    const double e = (p - tru.col(i)).norm();
    sq += e * e;
    sum += e;
    out.max_m = std::max(out.max_m, e);
  }
  out.rmse_m = std::sqrt(sq / static_cast<double>(n));
  out.mean_m = sum / static_cast<double>(n);
  const Pose3d end_error = MotionError(truth, estimate, 0, truth.size() - 1);
  out.end_point_m = end_error.translation().norm();
  out.end_rotation_deg = kRadToDeg * AngleRad(end_error.linear());
  out.end_point_percent = out.path_length_m > 0.0 ? 100.0 * out.end_point_m / out.path_length_m : 0.0;
  return out;
}

}  // namespace semap
