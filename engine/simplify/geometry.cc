#include "engine/simplify/internal/geometry.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <numeric>

#include "engine/core/check.h"

namespace semap::simplify {

namespace {
struct VectorAdaptor {
  const std::vector<Eigen::Vector3d>* points;
  size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, VectorAdaptor>,
                                                 VectorAdaptor, 3, std::uint32_t>;
constexpr size_t kLeafSize = 16;
}  // namespace

struct PointIndex::Impl {
  explicit Impl(const std::vector<Eigen::Vector3d>& points)
      : adaptor{&points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)) {}
  VectorAdaptor adaptor;
  Tree tree;
};

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points) : impl_(std::make_unique<Impl>(points)) {}
PointIndex::~PointIndex() = default;

void PointIndex::Radius(const Eigen::Vector3d& query, double radius_m,
                        std::vector<std::uint32_t>* out) const {
  out->clear();
  if (impl_->adaptor.points->empty()) return;
  thread_local std::vector<std::pair<std::uint32_t, double>> matches;
  matches.clear();
  nanoflann::SearchParams params;
  params.sorted = false;
  impl_->tree.radiusSearch(query.data(), radius_m * radius_m, matches, params);
  out->reserve(matches.size());
  for (const auto& m : matches) out->push_back(m.first);
}

void PointIndex::Knn(const Eigen::Vector3d& query, int k, std::vector<std::uint32_t>* out) const {
  const size_t n = std::min<size_t>(static_cast<size_t>(std::max(k, 0)), impl_->adaptor.points->size());
  out->resize(n);
  if (n == 0) return;
  thread_local std::vector<double> dists;
  dists.resize(n);
  const size_t found = impl_->tree.knnSearch(query.data(), n, out->data(), dists.data());
  out->resize(found);
}

Plane Plane::FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  Plane p;
  p.normal = normal.normalized();
  p.offset = -p.normal.dot(point);
  // Any unit vector not parallel to n gives the in-plane frame.
  const Eigen::Vector3d helper =
      std::abs(p.normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  p.u = p.normal.cross(helper).normalized();
  p.v = p.normal.cross(p.u);
  return p;
}

PcaResult Pca(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& neighbours) {
  PcaResult r;
  if (neighbours.size() < 3) return r;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto i : neighbours) mean += points[i];
  mean /= static_cast<double>(neighbours.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto i : neighbours) {
    const Eigen::Vector3d d = points[i] - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = lambda.sum();
  r.normal = eig.eigenvectors().col(0);
  r.surface_variation = sum > 0.0 ? lambda(0) / sum : 0.0;
  r.valid = true;
  return r;
}

std::optional<Plane> FitPlaneRansac(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::uint32_t>& indices, double threshold_m,
                                    int iterations, int max_points, std::mt19937_64& rng) {
  if (indices.size() < 3) return std::nullopt;
  // The evaluation sample: every member, or max_points of them drawn without replacement.
  std::vector<std::uint32_t> sample = indices;
  if (sample.size() > static_cast<size_t>(max_points)) {
    for (size_t i = 0; i < static_cast<size_t>(max_points); ++i) {
      std::uniform_int_distribution<size_t> pick(i, sample.size() - 1);
      std::swap(sample[i], sample[pick(rng)]);
    }
    sample.resize(static_cast<size_t>(max_points));
  }
  std::uniform_int_distribution<size_t> pick(0, sample.size() - 1);
  std::optional<Plane> best;
  size_t best_inliers = 0;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::Vector3d& a = points[sample[pick(rng)]];
    const Eigen::Vector3d& b = points[sample[pick(rng)]];
    const Eigen::Vector3d& c = points[sample[pick(rng)]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    const Plane h = Plane::FromPointNormal(a, n);
    size_t inliers = 0;
    for (auto i : sample) inliers += std::abs(h.SignedDistance(points[i])) <= threshold_m ? 1 : 0;
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = h;
    }
  }
  if (!best) return std::nullopt;
  // Least-squares refit (PCA) on the inliers of the best hypothesis.
  std::vector<std::uint32_t> inliers;
  for (auto i : sample) {
    if (std::abs(best->SignedDistance(points[i])) <= threshold_m) inliers.push_back(i);
  }
  const PcaResult pca = Pca(points, inliers);
  if (!pca.valid) return best;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (auto i : inliers) centroid += points[i];
  centroid /= static_cast<double>(inliers.size());
  return Plane::FromPointNormal(centroid, pca.normal);
}

}  // namespace semap::simplify
