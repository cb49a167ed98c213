#include "engine/simplify/simplify.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <sstream>

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
  SimplifyOptions options;
  throw InvalidOption(KeyOf(options, options.method),
                      "unknown simplification method '" + name + "', expected one of " + choices);
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
  CheckDeclaredRanges(*this);
  if (min_conservation > target_conservation) {
    std::ostringstream bound;
    bound << "must be <= " << KeyOf(*this, target_conservation) << " (" << target_conservation << ")";
    throw OptionError(*this, min_conservation, bound.str());
  }
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
