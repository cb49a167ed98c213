// Geometry shared by the simplification methods: a KD-tree (nanoflann, hidden behind a pimpl); RANSAC
// planes and PCA normals from engine/core/plane_fit.h. Not API.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "engine/core/plane_fit.h"

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

// Plane, FitPlaneRansac, RansacIterationsNeeded, PcaResult and Pca: engine/core/plane_fit.h.
using semap::FitPlaneRansac;
using semap::Pca;
using semap::PcaResult;
using semap::Plane;
using semap::RansacIterationsNeeded;

// Flips `normal` so that it faces `viewpoint` from `point` (n·(viewpoint − point) ≥ 0).
inline Eigen::Vector3d OrientTowards(const Eigen::Vector3d& normal, const Eigen::Vector3d& point,
                                     const Eigen::Vector3d& viewpoint) {
  return normal.dot(viewpoint - point) >= 0.0 ? normal : Eigen::Vector3d(-normal);
}

}  // namespace semap::simplify
