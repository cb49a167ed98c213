// The simplification methods on a "context" cloud, shared by Simplify() and WindowedSimplifier. Not API.
//
// A context is a cloud whose leading `num_fixed` points were decided earlier (kept, never removed, but they
// count in densities, p̃, planes and regions) and whose remaining points are the candidates to decide.
// Batch simplification has num_fixed = 0.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"
#include "engine/simplify/internal/geometry.h"
#include "engine/simplify/simplify.h"

namespace semap::simplify {

// Group 0: never simplified. Semantic methods: 1 = ground role, 2 = wall role. Baselines: 1 = every point.
inline constexpr int kNumGroups = 3;
using GroupId = std::uint8_t;

// Running sum and count of region densities per group (points / m²), to form D̄.
struct DensitySums {
  std::array<double, kNumGroups> sum{};
  std::array<std::uint64_t, kNumGroups> count{};
  void Add(const DensitySums& other) {
    for (int g = 0; g < kNumGroups; ++g) {
      sum[g] += other.sum[g];
      count[g] += other.count[g];
    }
  }
  // Mean density of group g, or 0 without any region.
  double Mean(int g) const { return count[g] > 0 ? sum[g] / static_cast<double>(count[g]) : 0.0; }
};

struct MethodInput {
  const LabelledCloud* cloud = nullptr;  // the context (positions; camera_index/centres when present)
  std::size_t num_fixed = 0;             // leading decided points
  std::vector<Label> labels;             // per point (the unlabelled id where the cloud has none)
  std::vector<GroupId> groups;           // per point
  DensitySums prior_densities;  // region densities of earlier frames (windowed), added to this call's

  std::size_t size() const { return labels.size(); }
  bool IsCandidate(std::size_t i) const { return i >= num_fixed; }
  // The observing camera centre of point i, if the cloud has cameras.
  const Eigen::Vector3d* Viewpoint(std::size_t i) const {
    return cloud->camera_index.empty() ? nullptr : &cloud->camera_centers_world[cloud->camera_index[i]];
  }
};

// Builds the input for `cloud`: semantic = groups from the class map roles, else every point in group 1.
MethodInput MakeMethodInput(const LabelledCloud& cloud, const ClassMap& class_map, bool semantic,
                            std::size_t num_fixed);

struct MethodOutput {
  std::vector<std::uint8_t> removed;  // per context point; only candidates may be 1
  DensitySums batch_densities;        // the region densities this call computed, per group
  std::array<bool, kNumGroups> has_plane{};
};

enum class RegionShape : std::uint8_t { kRadius, kKnn };
enum class ConservationRule : std::uint8_t { kLinear, kAdaptive, kAdaptiveClass };

// LS / AS / ACS (and LSB / ASB with a non-semantic input). See regional.cc for how regions combine.
MethodOutput RunRegional(const MethodInput& in, ConservationRule rule, RegionShape shape,
                         const SimplifyOptions& options, std::mt19937_64& rng);
// PS (use_boundary = true) and PSB (false: P_c = P_I everywhere).
MethodOutput RunProbabilistic(const MethodInput& in, bool use_boundary, const SimplifyOptions& options,
                              std::mt19937_64& rng);
// Non-semantic baselines on a whole cloud: removed mask per point.
std::vector<std::uint8_t> RunGeometricBaseline(const LabelledCloud& cloud, const SimplifyOptions& options,
                                               std::mt19937_64& rng);
std::vector<std::uint8_t> RunVoxelGrid(const LabelledCloud& cloud, const SimplifyOptions& options);
std::vector<std::uint8_t> RunHierarchy(const LabelledCloud& cloud, const SimplifyOptions& options);

// Runs options.method on a context whose `num_fixed` leading points are decided (never removed).
// Region methods add `prior` to this call's region densities to form D̄; `densities` (optional) receives
// this call's. The random generator is seeded from options.seed. Returns the removed mask per point.
std::vector<std::uint8_t> RunMethod(const LabelledCloud& cloud, const ClassMap& class_map,
                                    const SimplifyOptions& options, std::size_t num_fixed,
                                    const DensitySums& prior, DensitySums* densities);
// Fills kept_indices (relative to `offset`), per_class and `in` from the candidates [offset, n).
void CollectResult(const LabelledCloud& cloud, const ClassMap& class_map,
                   const std::vector<std::uint8_t>& removed, std::size_t offset, SimplifyResult* result);

// ---- helpers shared by regional.cc and probabilistic.cc ----

// One RANSAC plane per group ≥ 1 over every context point of the group (nullopt-equivalent: has = false).
struct GroupPlanes {
  std::array<Plane, kNumGroups> plane;
  std::array<bool, kNumGroups> has{};
};
GroupPlanes FitGroupPlanes(const MethodInput& in, const SimplifyOptions& options, std::mt19937_64& rng);

// r(p) = (n_i − n_l)ᵀ(n_i − n_l) for every candidate of a group with a plane (others: 0). n_i is the PCA
// normal over the normal_k nearest context points; both n_i and n_l are oriented towards the point's
// observing camera (without cameras, n_i is flipped to n_i·n_l ≥ 0), so r measures the angle between the
// surfaces, not an arbitrary sign: r = 0 when parallel, 2 when perpendicular.
std::vector<float> RankingScores(const MethodInput& in, const GroupPlanes& planes, const PointIndex& index,
                                 const SimplifyOptions& options);

// Runs body(begin, end) over [0, n) in fixed-size blocks with TBB. Outputs must be per index.
void ParallelBlocks(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body);

}  // namespace semap::simplify
