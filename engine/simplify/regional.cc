// LS / AS / ACS with radius (R) or KNN (K) regions, and the baselines LSB / ASB (one group, p̃ = 0).
//
// Our reading of the paper's region procedure:
// - Every candidate point p_i of a target group is the centre of a region ρ_i (all context points within
//   region_radius_m, or its region_k nearest context points, any label).
// - D(ρ_i) = |ρ_i| / area. R: area = π R². K: the region's points are expressed in the frame (u, v, n_l) of
//   the group's RANSAC plane; area = the largest face of their axis-aligned bounding box in that frame
//   (max of Δu·Δv, Δu·Δn, Δv·Δn), which is Δu·Δv for a flat patch and still sensible for a thick one.
// - D̄ = mean of D over the group's regions (plus earlier frames' regions in the windowed simplifier).
// - p̃ = share of the region's points whose label differs from the centre's label.
// - Overlapping regions combine sequentially, regions taken in a random (seeded) order, and every point is
//   decided once: region ρ_i holds n candidates of its centre's group and wants ceil(c·n) of them alive (it
//   discards floor((1 − c)·n), the paper's "last (1 − c)·|ρ_i|"). Points of the group it contains that are
//   already decided and kept (by earlier regions, or fixed points of earlier frames) count towards that
//   quota; its undecided candidates fill what is left of it, best ranked (smallest r) first, and the others
//   are removed. All its candidates are then decided. A region thus ends with about its own share c (more
//   if earlier regions already kept more), so the overall conservation at average density is about c̄.
//   (Letting later regions also remove points that earlier ones kept compounds the overlaps: on a uniform
//   plane it kept 18 % instead of 40 % for c̄ = 0.4.)
// - Regions centred on an already decided point are skipped: with decisions made once, such a region could
//   only decide undecided points, which the regions centred on them (or others) decide anyway. This keeps
//   the cost near one region query per ~c·|ρ| points instead of one per point (the paper's "a region for
//   each point" is the upper bound).
// - D̄ is estimated from the regions of at most density_samples random centres per group (0 = all), so that
//   it is known before the sequential pass.
// - Streaming (windowed) contexts: D counts every context point, while D̄ is the mean over the window of
//   the regions' *candidate* densities (a single frame's density), so an area already covered by decided
//   points reads as denser than average; the quota is counted on the candidates, so a region whose decided
//   points already reach ceil(c·n) removes all its new points. In batch mode both coincide with the above.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "engine/core/check.h"
#include "engine/simplify/conservation.h"
#include "engine/simplify/internal/methods.h"

namespace semap::simplify {

namespace {

struct RegionStats {
  double density = 0.0;            // points / m² (every context point)
  double candidate_density = 0.0;  // candidates / m² (what D̄ averages)
  double other_share = 0.0;        // p̃
};

void QueryRegion(const PointIndex& index, const Eigen::Vector3d& centre, RegionShape shape,
                 const SimplifyOptions& o, std::vector<std::uint32_t>* out) {
  if (shape == RegionShape::kRadius) {
    index.Radius(centre, o.region_radius_m, out);
  } else {
    index.Knn(centre, o.region_k, out);
  }
}

// Largest face of the axis-aligned bounding box of `region` in the plane frame (u, v, n).
double KnnRegionArea(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::uint32_t>& region,
                     const Plane& plane) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (auto j : region) {
    const Eigen::Vector3d q(plane.u.dot(pts[j]), plane.v.dot(pts[j]), plane.normal.dot(pts[j]));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector3d e = hi - lo;
  return std::max({e.x() * e.y(), e.x() * e.z(), e.y() * e.z()});
}

RegionStats ComputeRegionStats(const MethodInput& in, std::size_t centre,
                               const std::vector<std::uint32_t>& region, RegionShape shape,
                               const Plane& plane, const SimplifyOptions& o) {
  RegionStats s;
  const auto n = static_cast<double>(region.size());
  double area = std::numbers::pi * o.region_radius_m * o.region_radius_m;
  if (shape == RegionShape::kKnn) area = KnnRegionArea(in.cloud->positions_world, region, plane);
  // A degenerate region (all points on a line or coincident) has no area: treat it as one of the
  // smallest representable areas so that it reads as very dense.
  constexpr double kMinAreaM2 = 1e-9;
  s.density = n / std::max(area, kMinAreaM2);
  std::size_t candidates = 0;
  for (auto j : region) candidates += in.IsCandidate(j) ? 1 : 0;
  s.candidate_density = static_cast<double>(candidates) / std::max(area, kMinAreaM2);
  std::size_t other = 0;
  for (auto j : region) other += in.labels[j] != in.labels[centre] ? 1 : 0;
  s.other_share = region.empty() ? 0.0 : static_cast<double>(other) / n;
  return s;
}

double Conservation(ConservationRule rule, double d_norm, double other_share, const SimplifyOptions& o) {
  switch (rule) {
    case ConservationRule::kLinear:
      return LinearConservation(d_norm, o.target_conservation, o.min_conservation);
    case ConservationRule::kAdaptive:
      return AdaptiveConservation(d_norm, o.target_conservation, o.adaptive_stretch, o.min_conservation);
    case ConservationRule::kAdaptiveClass:
      return AdaptiveClassConservation(d_norm, other_share, o.target_conservation, o.adaptive_stretch,
                                       o.min_conservation);
  }
  return 1.0;
}

}  // namespace

MethodOutput RunRegional(const MethodInput& in, ConservationRule rule, RegionShape shape,
                         const SimplifyOptions& o, std::mt19937_64& rng) {
  const auto& pts = in.cloud->positions_world;
  MethodOutput out;
  out.removed.assign(in.size(), 0);
  const GroupPlanes planes = FitGroupPlanes(in, o, rng);
  out.has_plane = planes.has;

  // Region centres: the candidates of groups with a plane.
  std::vector<std::uint32_t> centres;
  for (std::size_t i = in.num_fixed; i < in.size(); ++i) {
    if (in.groups[i] != 0 && planes.has[in.groups[i]]) centres.push_back(static_cast<std::uint32_t>(i));
  }
  if (centres.empty()) return out;

  const PointIndex index(pts);
  const std::vector<float> rank = RankingScores(in, planes, index, o);

  // D̄ per group: the mean candidate density over the regions of (at most density_samples) random centres
  // of the group, computed in parallel.
  std::array<std::vector<std::uint32_t>, kNumGroups> samples;
  for (auto c : centres) samples[in.groups[c]].push_back(c);
  std::vector<std::uint32_t> sample_centres;
  for (auto& members : samples) {
    const std::size_t n =
        o.density_samples > 0 ? std::min<std::size_t>(members.size(), o.density_samples) : members.size();
    for (std::size_t k = 0; k < n; ++k) {
      std::uniform_int_distribution<std::size_t> pick(k, members.size() - 1);
      std::swap(members[k], members[pick(rng)]);
      sample_centres.push_back(members[k]);
    }
  }
  std::vector<double> sample_density(sample_centres.size());
  ParallelBlocks(sample_centres.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t> region;
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t c = sample_centres[k];
      QueryRegion(index, pts[c], shape, o, &region);
      sample_density[k] =
          ComputeRegionStats(in, c, region, shape, planes.plane[in.groups[c]], o).candidate_density;
    }
  });
  for (std::size_t k = 0; k < sample_centres.size(); ++k) {
    const GroupId g = in.groups[sample_centres[k]];
    out.batch_densities.sum[g] += sample_density[k];
    out.batch_densities.count[g] += 1;
  }
  DensitySums all = in.prior_densities;
  all.Add(out.batch_densities);

  // Pass 2 (sequential, random region order): quotas, each point decided once.
  std::vector<std::uint32_t> order(centres.size());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<std::uint8_t> decided(in.size(), 0);
  std::vector<std::uint32_t> region;
  std::vector<std::uint32_t> undecided;
  // Best first: smallest r, ties broken by index so that the result is reproducible.
  auto better = [&](std::uint32_t a, std::uint32_t b) {
    return rank[a] != rank[b] ? rank[a] < rank[b] : a < b;
  };
  for (const std::uint32_t k : order) {
    const std::uint32_t c = centres[k];
    if (decided[c]) continue;  // see the header comment: its region could only decide what others will
    const GroupId g = in.groups[c];
    const double mean = all.Mean(g);
    if (mean <= 0.0) continue;
    QueryRegion(index, pts[c], shape, o, &region);
    const RegionStats stats = ComputeRegionStats(in, c, region, shape, planes.plane[g], o);
    const double conservation = Conservation(rule, stats.density / mean, stats.other_share, o);
    std::size_t n_candidates = 0;
    std::size_t kept_already = 0;
    undecided.clear();
    for (auto j : region) {
      if (in.groups[j] != g) continue;
      const bool candidate = in.IsCandidate(j);
      n_candidates += candidate ? 1 : 0;
      if (!candidate || (decided[j] && !out.removed[j])) {
        ++kept_already;
      } else if (!decided[j]) {
        undecided.push_back(j);
      }
    }
    if (undecided.empty()) continue;
    const std::size_t quota = n_candidates - DiscardCount(conservation, n_candidates);
    const std::size_t keep = std::min(undecided.size(), quota > kept_already ? quota - kept_already : 0);
    std::partial_sort(undecided.begin(), undecided.begin() + static_cast<std::ptrdiff_t>(keep),
                      undecided.end(), better);
    for (std::size_t e = 0; e < undecided.size(); ++e) {
      decided[undecided[e]] = 1;
      out.removed[undecided[e]] = e < keep ? 0 : 1;
    }
  }
  return out;
}

}  // namespace semap::simplify
