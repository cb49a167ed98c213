#include "engine/simplify/simplify.h"

#include <algorithm>
#include <chrono>
#include <map>

#include "engine/core/check.h"
#include "engine/simplify/internal/methods.h"

namespace semap {

namespace {
struct MethodName {
  SimplifyMethod method;
  const char* name;
};
constexpr MethodName kNames[] = {
    {SimplifyMethod::kOriginal, "O"},
    {SimplifyMethod::kGeometricBaseline, "GB"},
    {SimplifyMethod::kLinearBaseline, "LSB"},
    {SimplifyMethod::kAdaptiveBaseline, "ASB"},
    {SimplifyMethod::kProbabilisticBaseline, "PSB"},
    {SimplifyMethod::kLinearRadius, "LSR"},
    {SimplifyMethod::kLinearKnn, "LSK"},
    {SimplifyMethod::kAdaptiveRadius, "ASR"},
    {SimplifyMethod::kAdaptiveKnn, "ASK"},
    {SimplifyMethod::kAdaptiveClassRadius, "ACSR"},
    {SimplifyMethod::kAdaptiveClassKnn, "ACSK"},
    {SimplifyMethod::kProbabilistic, "PS"},
    {SimplifyMethod::kVoxel, "voxel"},
    {SimplifyMethod::kHierarchy, "hierarchy"},
};
}  // namespace

const char* SimplifyMethodName(SimplifyMethod method) {
  for (const auto& n : kNames) {
    if (n.method == method) return n.name;
  }
  return "?";
}

const std::vector<SimplifyMethod>& AllSimplifyMethods() {
  static const std::vector<SimplifyMethod> all = [] {
    std::vector<SimplifyMethod> v;
    for (const auto& n : kNames) v.push_back(n.method);
    return v;
  }();
  return all;
}

SimplifyMethod SimplifyMethodFromName(const std::string& name) {
  std::string choices;
  for (const auto& n : kNames) {
    if (name == n.name) return n.method;
    if (!choices.empty()) choices += '|';
    choices += n.name;
  }
  throw InvalidOption("method", "unknown simplification method '" + name + "', expected one of " + choices);
}

bool IsSemanticMethod(SimplifyMethod method) {
  switch (method) {
    case SimplifyMethod::kLinearRadius:
    case SimplifyMethod::kLinearKnn:
    case SimplifyMethod::kAdaptiveRadius:
    case SimplifyMethod::kAdaptiveKnn:
    case SimplifyMethod::kAdaptiveClassRadius:
    case SimplifyMethod::kAdaptiveClassKnn:
    case SimplifyMethod::kProbabilistic:
      return true;
    default:
      return false;
  }
}

void SimplifyOptions::Check() const {
  SEMAP_CHECK_OPTION(region_radius_m > 0.0, "region_radius_m", region_radius_m, "must be > 0");
  SEMAP_CHECK_OPTION(region_k >= 3, "region_k", region_k, "must be >= 3");
  SEMAP_CHECK_OPTION(density_samples >= 0, "density_samples", density_samples, "must be >= 0 (0 = all)");
  SEMAP_CHECK_OPTION(normal_k >= 3, "normal_k", normal_k, "must be >= 3");
  SEMAP_CHECK_OPTION(target_conservation > 0.0 && target_conservation < 1.0, "target_conservation",
                     target_conservation, "must be in (0, 1)");
  SEMAP_CHECK_OPTION(adaptive_stretch > 0.0, "adaptive_stretch", adaptive_stretch, "must be > 0");
  SEMAP_CHECK_OPTION(min_conservation >= 0.0 && min_conservation <= target_conservation, "min_conservation",
                     min_conservation, "must be in [0, target_conservation]");
  SEMAP_CHECK_OPTION(ps_region_divisor >= 1, "ps_region_divisor", ps_region_divisor, "must be >= 1");
  SEMAP_CHECK_OPTION(ps_boundary_share > 0.0 && ps_boundary_share <= 1.0, "ps_boundary_share",
                     ps_boundary_share, "must be in (0, 1]");
  SEMAP_CHECK_OPTION(ps_interior_sigma_m > 0.0, "ps_interior_sigma_m", ps_interior_sigma_m, "must be > 0");
  SEMAP_CHECK_OPTION(ps_boundary_sigma_m > 0.0, "ps_boundary_sigma_m", ps_boundary_sigma_m, "must be > 0");
  SEMAP_CHECK_OPTION(ps_svm_c > 0.0, "ps_svm_c", ps_svm_c, "must be > 0");
  SEMAP_CHECK_OPTION(ps_svm_max_samples >= 2, "ps_svm_max_samples", ps_svm_max_samples, "must be >= 2");
  SEMAP_CHECK_OPTION(ransac_threshold_m > 0.0, "ransac_threshold_m", ransac_threshold_m, "must be > 0");
  SEMAP_CHECK_OPTION(ransac_iterations >= 1, "ransac_iterations", ransac_iterations, "must be >= 1");
  SEMAP_CHECK_OPTION(ransac_max_points >= 3, "ransac_max_points", ransac_max_points, "must be >= 3");
  SEMAP_CHECK_OPTION(ransac_confidence > 0.0 && ransac_confidence <= 1.0, "ransac_confidence",
                     ransac_confidence, "must be in (0, 1]");
  SEMAP_CHECK_OPTION(gb_flatness_threshold >= 0.0 && gb_flatness_threshold <= 1.0 / 3.0,
                     "gb_flatness_threshold", gb_flatness_threshold, "must be in [0, 1/3]");
  SEMAP_CHECK_OPTION(gb_flat_keep_probability >= 0.0 && gb_flat_keep_probability <= 1.0,
                     "gb_flat_keep_probability", gb_flat_keep_probability, "must be in [0, 1]");
  SEMAP_CHECK_OPTION(voxel_size_m > 0.0, "voxel_size_m", voxel_size_m, "must be > 0");
  SEMAP_CHECK_OPTION(hierarchy_cluster_size >= 1, "hierarchy_cluster_size", hierarchy_cluster_size,
                     "must be >= 1");
  SEMAP_CHECK_OPTION(hierarchy_max_variation > 0.0 && hierarchy_max_variation <= 1.0 / 3.0,
                     "hierarchy_max_variation", hierarchy_max_variation, "must be in (0, 1/3]");
  SEMAP_CHECK_OPTION(window_frames >= 1, "window_frames", window_frames, "must be >= 1");
}

namespace simplify {
// The removed mask of any method on a context (num_fixed leading decided points; baselines that do not use
// regions require num_fixed = 0). `densities` (optional) receives the batch's region densities.
std::vector<std::uint8_t> RunMethod(const LabelledCloud& cloud, const ClassMap& class_map,
                                    const SimplifyOptions& o, std::size_t num_fixed, const DensitySums& prior,
                                    DensitySums* densities) {
  std::mt19937_64 rng(o.seed);
  auto regional = [&](ConservationRule rule, RegionShape shape, bool semantic) {
    MethodInput in = MakeMethodInput(cloud, class_map, semantic, num_fixed);
    in.prior_densities = prior;
    MethodOutput out = RunRegional(in, rule, shape, o, rng);
    if (densities) *densities = out.batch_densities;
    return out.removed;
  };
  auto probabilistic = [&](bool semantic) {
    MethodInput in = MakeMethodInput(cloud, class_map, semantic, num_fixed);
    in.prior_densities = prior;
    MethodOutput out = RunProbabilistic(in, semantic, o, rng);
    if (densities) *densities = out.batch_densities;
    return out.removed;
  };
  auto candidates_only = [&](std::vector<std::uint8_t> removed) {
    std::fill(removed.begin(), removed.begin() + static_cast<std::ptrdiff_t>(num_fixed), 0);
    return removed;
  };
  using M = SimplifyMethod;
  switch (o.method) {
    case M::kOriginal:
      return std::vector<std::uint8_t>(cloud.size(), 0);
    case M::kGeometricBaseline:
      return candidates_only(RunGeometricBaseline(cloud, o, rng));
    case M::kLinearBaseline:
      return regional(ConservationRule::kLinear, RegionShape::kRadius, false);
    case M::kAdaptiveBaseline:
      return regional(ConservationRule::kAdaptive, RegionShape::kRadius, false);
    case M::kProbabilisticBaseline:
      return probabilistic(false);
    case M::kLinearRadius:
      return regional(ConservationRule::kLinear, RegionShape::kRadius, true);
    case M::kLinearKnn:
      return regional(ConservationRule::kLinear, RegionShape::kKnn, true);
    case M::kAdaptiveRadius:
      return regional(ConservationRule::kAdaptive, RegionShape::kRadius, true);
    case M::kAdaptiveKnn:
      return regional(ConservationRule::kAdaptive, RegionShape::kKnn, true);
    case M::kAdaptiveClassRadius:
      return regional(ConservationRule::kAdaptiveClass, RegionShape::kRadius, true);
    case M::kAdaptiveClassKnn:
      return regional(ConservationRule::kAdaptiveClass, RegionShape::kKnn, true);
    case M::kProbabilistic:
      return probabilistic(true);
    case M::kVoxel:
      return candidates_only(RunVoxelGrid(cloud, o));
    case M::kHierarchy:
      return candidates_only(RunHierarchy(cloud, o));
  }
  SEMAP_ASSERT(false, "unhandled method");
  return {};
}

// Kept indices (relative to `offset`) and per-label statistics over the candidates [offset, n).
void CollectResult(const LabelledCloud& cloud, const ClassMap& class_map,
                   const std::vector<std::uint8_t>& removed, std::size_t offset, SimplifyResult* result) {
  std::map<Label, ClassSimplifyStats> stats;
  for (std::size_t i = offset; i < cloud.size(); ++i) {
    const Label label = cloud.labels.empty() ? class_map.unlabelled_id() : cloud.labels[i];
    auto& s = stats[label];
    s.label = label;
    ++s.in;
    if (removed[i]) {
      ++s.removed;
    } else {
      ++s.kept;
      result->kept_indices.push_back(static_cast<std::uint32_t>(i - offset));
    }
  }
  result->in = cloud.size() - offset;
  for (const auto& [label, s] : stats) result->per_class.push_back(s);
}
}  // namespace simplify

SimplifyResult Simplify(const LabelledCloud& cloud, const ClassMap& class_map,
                        const SimplifyOptions& options) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  const auto removed = simplify::RunMethod(cloud, class_map, options, 0, {}, nullptr);
  SimplifyResult result;
  simplify::CollectResult(cloud, class_map, removed, 0, &result);
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

LabelledCloud ApplySimplification(const LabelledCloud& cloud, const SimplifyResult& result) {
  return cloud.Subset(result.kept_indices);
}

}  // namespace semap
