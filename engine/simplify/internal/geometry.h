// Geometry shared by the simplification methods: a KD-tree (nanoflann, hidden behind a pimpl), RANSAC
// planes and PCA normals. Not API.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <vector>

namespace semap::simplify {

// KD-tree over a point array that must outlive it. Const queries are thread-safe.
class PointIndex {
 public:
  explicit PointIndex(const std::vector<Eigen::Vector3d>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  // Indices of the points within `radius_m` of `query`, in the tree's (deterministic, unsorted) order.
  // `out` is overwritten.
  void Radius(const Eigen::Vector3d& query, double radius_m, std::vector<std::uint32_t>* out) const;
  // The min(k, size) nearest points (nearest first). `out` is overwritten.
  void Knn(const Eigen::Vector3d& query, int k, std::vector<std::uint32_t>* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Fixed-radius neighbourhoods by a uniform grid whose cells have the radius as edge: a query reads the 27
// cells around the query's cell and keeps the points within the radius. Cheaper to build than a KD-tree
// (one sort) and as fast to query at a fixed radius; PS builds one per frame over the window's context.
// The point array must outlive the grid. Const queries are thread-safe.
class RadiusGrid {
 public:
  RadiusGrid(const std::vector<Eigen::Vector3d>& points, double radius_m);

  // Indices of the points within radius_m (distance ≤ radius_m) of `query`, cell by cell in a fixed order
  // and ascending within a cell: the same points and order for the same input. `out` is overwritten.
  void Radius(const Eigen::Vector3d& query, std::vector<std::uint32_t>* out) const;

 private:
  // A slot of the open-addressing table of occupied cells (linear probing; key kEmpty = free).
  struct Slot {
    std::uint64_t key;
    std::uint32_t begin, end;  // range of order_
  };
  std::uint64_t Key(std::int64_t x, std::int64_t y, std::int64_t z) const;
  std::int64_t CellOf(double coordinate) const;
  std::size_t Home(std::uint64_t key) const;  // the key's first slot

  const std::vector<Eigen::Vector3d>* points_;
  double radius_m_;
  std::vector<std::uint32_t> order_;  // point indices by cell key, then ascending
  std::vector<Slot> slots_;           // a power of two, at least twice the occupied cells
  int slot_bits_ = 0;
};

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

// Flips `normal` so that it faces `viewpoint` from `point` (n·(viewpoint − point) ≥ 0).
inline Eigen::Vector3d OrientTowards(const Eigen::Vector3d& normal, const Eigen::Vector3d& point,
                                     const Eigen::Vector3d& viewpoint) {
  return normal.dot(viewpoint - point) >= 0.0 ? normal : Eigen::Vector3d(-normal);
}

}  // namespace semap::simplify
