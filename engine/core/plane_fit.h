// Planes through 3D points: RANSAC with least-squares refits, and the PCA of a neighbourhood (the
// simplification's class planes, the plane sweep's dominant directions).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace semap {

// A plane n·x + offset = 0 with |n| = 1 and an orthonormal in-plane frame (u, v, n).
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();

  static Plane FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  double SignedDistance(const Eigen::Vector3d& x) const { return normal.dot(x) + offset; }
  // In-plane coordinates (u, v) of x's orthogonal projection.
  Eigen::Vector2d Project(const Eigen::Vector3d& x) const { return {u.dot(x), v.dot(x)}; }
};

// RANSAC plane over points[indices]: at most `iterations` 3-point hypotheses, inliers (|distance| ≤
// threshold) counted on at most `max_points` random members, then two least-squares refits on the inliers
// among all the members (of the best hypothesis, then of the first refit).
// Adaptive stop: once the best hypothesis has inlier share w of the sample, RANSAC stops after
// RansacIterationsNeeded(w, confidence, iterations) hypotheses (confidence ≥ 1: always `iterations`).
// nullopt when fewer than 3 points or every hypothesis is degenerate.
std::optional<Plane> FitPlaneRansac(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::uint32_t>& indices, double threshold_m,
                                    int iterations, int max_points, double confidence, std::mt19937_64& rng);

// The hypotheses RANSAC needs to draw three inliers at least once with probability `confidence` when a share
// `inlier_share` of the points are inliers: ceil(log(1 − confidence) / log(1 − w³)), clamped to
// [1, max_iterations]; max_iterations when confidence ≥ 1 or w ≤ 0.
int RansacIterationsNeeded(double inlier_share, double confidence, int max_iterations);

// Tangent-plane approximation: PCA of points[neighbours]. `normal` is the eigenvector of the smallest
// eigenvalue (sign arbitrary), `surface_variation` = λ0 / (λ0 + λ1 + λ2) (0 when the points coincide).
struct PcaResult {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double surface_variation = 0.0;
  bool valid = false;  // false with fewer than 3 neighbours
};
PcaResult Pca(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& neighbours);

}  // namespace semap
