#include "engine/core/plane_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace semap {
namespace {

// RANSAC counts a hypothesis's inliers this many points at a time between its early-drop checks.
constexpr size_t kRansacChunk = 256;

}  // namespace

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

int RansacIterationsNeeded(double inlier_share, double confidence, int max_iterations) {
  if (confidence >= 1.0 || !(inlier_share > 0.0)) return max_iterations;
  const double all_inliers = std::pow(std::min(inlier_share, 1.0), 3);
  if (all_inliers >= 1.0) return std::min(1, max_iterations);
  const double needed = std::ceil(std::log(1.0 - confidence) / std::log(1.0 - all_inliers));
  return static_cast<int>(std::clamp(needed, 1.0, static_cast<double>(max_iterations)));
}

std::optional<Plane> FitPlaneRansac(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::uint32_t>& indices, double threshold_m,
                                    int iterations, int max_points, double confidence, std::mt19937_64& rng) {
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
  // The sample's coordinates, one array per axis: the counting loop below then reads them in order (and the
  // compiler can vectorise it) instead of gathering the points through their indices. The distance is
  // computed in the order SignedDistance computes it, n·x + offset.
  std::vector<double> xs(sample.size()), ys(sample.size()), zs(sample.size());
  for (size_t k = 0; k < sample.size(); ++k) {
    const Eigen::Vector3d& p = points[sample[k]];
    xs[k] = p.x();
    ys[k] = p.y();
    zs[k] = p.z();
  }
  std::optional<Plane> best;
  size_t best_inliers = 0;
  int needed = iterations;  // lowered as better hypotheses are found (adaptive stop)
  for (int it = 0; it < needed; ++it) {
    const Eigen::Vector3d& a = points[sample[pick(rng)]];
    const Eigen::Vector3d& b = points[sample[pick(rng)]];
    const Eigen::Vector3d& c = points[sample[pick(rng)]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    const Plane h = Plane::FromPointNormal(a, n);
    // Counted in chunks; a hypothesis that can no longer beat the best (inliers + points left ≤ best) is
    // dropped early: the same choice as counting every point.
    size_t inliers = 0;
    for (size_t begin = 0; begin < sample.size(); begin += kRansacChunk) {
      const size_t end = std::min(sample.size(), begin + kRansacChunk);
      const double nx = h.normal.x(), ny = h.normal.y(), nz = h.normal.z(), offset = h.offset;
      for (size_t k = begin; k < end; ++k) {
        inliers += std::abs(nx * xs[k] + ny * ys[k] + nz * zs[k] + offset) <= threshold_m ? 1 : 0;
      }
      if (inliers + (sample.size() - end) <= best_inliers) break;
    }
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = h;
      needed = RansacIterationsNeeded(static_cast<double>(inliers) / static_cast<double>(sample.size()),
                                      confidence, iterations);
    }
  }
  if (!best) return std::nullopt;
  // Least-squares refits (PCA) on the inliers among all the points: first of the best hypothesis, then of
  // that refit (so that any of the near-equal hypotheses an early stop may keep ends on the same plane).
  constexpr int kRefits = 2;
  Plane plane = *best;
  std::vector<std::uint32_t> inliers;
  for (int refit = 0; refit < kRefits; ++refit) {
    inliers.clear();
    for (auto i : indices) {
      if (std::abs(plane.SignedDistance(points[i])) <= threshold_m) inliers.push_back(i);
    }
    const PcaResult pca = Pca(points, inliers);
    if (!pca.valid) break;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (auto i : inliers) centroid += points[i];
    centroid /= static_cast<double>(inliers.size());
    plane = Plane::FromPointNormal(centroid, pca.normal);
  }
  return plane;
}

}  // namespace semap
