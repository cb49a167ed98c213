// Non-semantic baselines: GB (curvature), voxel grid, CGAL hierarchy clustering. They see the whole cloud.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/hierarchy_simplify_point_set.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include "engine/core/check.h"
#include "engine/simplify/internal/methods.h"

namespace semap::simplify {

// GB, in the spirit of the curvature-driven simplification the paper cites (Cignoni et al.): the surface
// variation σ = λ0 / (λ0 + λ1 + λ2) of the normal_k nearest points estimates the curvature; points with
// σ < gb_flatness_threshold lie on flat surfaces and are kept with probability gb_flat_keep_probability,
// every other point is kept. Draws are made in index order from the seeded generator.
std::vector<std::uint8_t> RunGeometricBaseline(const LabelledCloud& cloud, const SimplifyOptions& o,
                                               std::mt19937_64& rng) {
  const auto& pts = cloud.positions_world;
  std::vector<std::uint8_t> flat(pts.size(), 0);
  const PointIndex index(pts);
  ParallelBlocks(pts.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t> nn;
    for (std::size_t i = begin; i < end; ++i) {
      index.Knn(pts[i], o.normal_k, &nn);
      const PcaResult pca = Pca(pts, nn);
      flat[i] = pca.valid && pca.surface_variation < o.gb_flatness_threshold ? 1 : 0;
    }
  });
  std::vector<std::uint8_t> removed(pts.size(), 0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (flat[i] && uniform(rng) >= o.gb_flat_keep_probability) removed[i] = 1;
  }
  return removed;
}

namespace {
struct VoxelKey {
  std::int64_t x, y, z;
  bool operator==(const VoxelKey&) const = default;
};
struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    // Large primes mixing (Teschner et al. spatial hashing).
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
}  // namespace

// Voxel grid: every occupied cell of edge voxel_size_m keeps one point, the one nearest the centroid of the
// cell's points (lowest index on ties), so that the output is a subset of the input.
std::vector<std::uint8_t> RunVoxelGrid(const LabelledCloud& cloud, const SimplifyOptions& o) {
  const auto& pts = cloud.positions_world;
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::uint32_t count = 0;
    std::uint32_t best = 0;
    double best_d2 = std::numeric_limits<double>::infinity();
  };
  std::unordered_map<VoxelKey, Cell, VoxelKeyHash> cells;
  std::vector<VoxelKey> keys(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d q = (pts[i] / o.voxel_size_m).array().floor();
    keys[i] = {static_cast<std::int64_t>(q.x()), static_cast<std::int64_t>(q.y()),
               static_cast<std::int64_t>(q.z())};
    Cell& c = cells[keys[i]];
    c.sum += pts[i];
    ++c.count;
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Cell& c = cells[keys[i]];
    const double d2 = (pts[i] - c.sum / c.count).squaredNorm();
    if (d2 < c.best_d2) {
      c.best_d2 = d2;
      c.best = static_cast<std::uint32_t>(i);
    }
  }
  std::vector<std::uint8_t> removed(pts.size(), 1);
  for (const auto& [key, c] : cells) removed[c.best] = 0;
  return removed;
}

// CGAL::hierarchy_simplify_point_set: recursive PCA splits until a cluster has at most
// hierarchy_cluster_size points and a surface variation at most hierarchy_max_variation; each final cluster
// keeps its point nearest the centroid. Deterministic (no randomness).
std::vector<std::uint8_t> RunHierarchy(const LabelledCloud& cloud, const SimplifyOptions& o) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Item = std::pair<Kernel::Point_3, std::uint32_t>;
  std::vector<std::uint8_t> removed(cloud.size(), 1);
  if (cloud.empty()) return removed;
  std::vector<Item> items;
  items.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud.positions_world[i];
    items.emplace_back(Kernel::Point_3(p.x(), p.y(), p.z()), static_cast<std::uint32_t>(i));
  }
  const auto first_removed = CGAL::hierarchy_simplify_point_set(
      items, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<Item>())
                 .size(static_cast<unsigned int>(o.hierarchy_cluster_size))
                 .maximum_variation(o.hierarchy_max_variation));
  for (auto it = items.begin(); it != first_removed; ++it) removed[it->second] = 0;
  return removed;
}

}  // namespace semap::simplify
