// PS (probabilistic simplification) and its baseline PSB.
//
// Our reading of the paper:
// - N_r = floor(|candidates of the group| / ps_region_divisor) region centres per target group, drawn
//   uniformly without replacement among the group's candidates ("|ρ| the size of the cloud" read as the
//   size of the class's cloud, since the centres are drawn among the class's points).
// - Each region: the context points within region_radius_m of the centre (any label); D = |ρ| / (π R²);
//   d̃ = D / D̄ (D̄ the mean over the group's PS regions; in a windowed context D counts every context
//   point and D̄ averages the regions' candidate densities, so areas already covered by decided points
//   read as denser and lose more); p̃ = share of points with another label than the
//   centre's.
// - P_c = P_I when p̃ < ps_boundary_share, else P_B, applied to the region's candidates of the centre's group:
//   P_I = 1 − exp(−|x − μ|² / (2 d̃ σ_I²)), x and μ (the centre) projected on the group's RANSAC plane π_l
//       (the paper's N(μ, Σ), Σ = diag(d̃σ², d̃σ²), normalised to peak 1 so that P_I ∈ [0, 1)).
//   P_B = exp(−d² / (2 σ_B²)), d = distance on π_l to the line separating "label of the centre" from
//       "other labels", a linear soft-margin SVM (libsvm's C_SVC problem with a linear kernel, solved by
//       TrainLinearSvm, internal/linear_svm.h) on the projected region.
//       If the SVM cannot be trained or degenerates (|w| = 0), P_I is used for that region.
// - D̄ is estimated from at most density_samples regions per group (a uniform sample of the centres).
// - The SVM is trained on at most ps_svm_max_samples points of the region (evenly strided): near the camera
//   a 0.3 m region of a dense stereo cloud holds thousands of points, and a 2-D line needs far fewer.
// - A point is decided once, by the first region (in a random, seeded order) that contains it: it is removed
//   when a uniform draw in [0, 1) exceeds P_c. Points in no region are kept (the paper notes that some areas
//   may stay uncovered). Deciding once (rather than removing a point whenever any region's draw fails)
//   keeps the kept share of an interior area near E[P_I] instead of compounding the overlaps.
// - Streaming (windowed contexts, decided points present): like LS's quota, the decided points of the
//   group inside a region count against what the region would keep: with E = Σ P_c over the region's
//   candidates (what a fresh frame would keep there) and K the decided points, every candidate's P_c is
//   multiplied by max(0, 1 − K / E); a region already holding E decided points keeps no new ones. In batch
//   mode (no decided points) the factor is 1.
// - PSB: the whole cloud is one group and P_c = P_I everywhere (no boundaries without semantics).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>

#include "engine/core/check.h"
#include "engine/simplify/conservation.h"
#include "engine/simplify/internal/linear_svm.h"
#include "engine/simplify/internal/methods.h"

namespace semap::simplify {

namespace {

struct Boundary {
  Eigen::Vector2d normal;  // unit normal of the line in plane coordinates (metres)
  double offset = 0.0;     // line: normal · x + offset = 0 (x in metres on the plane)
};

// Fits the class boundary on the plane: `xy` in metres relative to the region centre, `positive` = label of
// the centre. Coordinates are scaled by 1/scale_m before training (unit-size problem for the solver).
std::optional<Boundary> FitBoundary(std::vector<Eigen::Vector2d>& xy, const std::vector<int>& positive,
                                    double scale_m, double svm_c) {
  // As cv::ml::SVM was set up here before: C_SVC, LINEAR, ε 1e-5, at most 2000 iterations.
  constexpr int kMaxIterations = 2000;
  constexpr double kEpsilon = 1e-5;
  for (auto& x : xy) x /= scale_m;
  const auto svm = TrainLinearSvm(xy, positive, LinearSvmOptions{svm_c, kEpsilon, kMaxIterations});
  if (!svm) return std::nullopt;
  const double norm = svm->w.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return std::nullopt;
  // decision(x') = w·x' − rho with x' = x / scale  ⇒  line (w/|w|)·x − rho·scale/|w| = 0 in metres.
  return Boundary{svm->w / norm, -svm->rho * scale_m / norm};
}

}  // namespace

MethodOutput RunProbabilistic(const MethodInput& in, bool use_boundary, const SimplifyOptions& o,
                              std::mt19937_64& rng) {
  const auto& pts = in.cloud->positions_world;
  MethodOutput out;
  out.removed.assign(in.size(), 0);
  const GroupPlanes planes = FitGroupPlanes(in, o, rng);
  out.has_plane = planes.has;

  // Region centres: N_r random candidates per group with a plane.
  std::vector<std::uint32_t> centres;
  for (int g = 1; g < kNumGroups; ++g) {
    if (!planes.has[g]) continue;
    std::vector<std::uint32_t> members;
    for (std::size_t i = in.num_fixed; i < in.size(); ++i) {
      if (in.groups[i] == g) members.push_back(static_cast<std::uint32_t>(i));
    }
    const std::size_t n_regions = members.size() / static_cast<std::size_t>(o.ps_region_divisor);
    for (std::size_t k = 0; k < n_regions; ++k) {
      std::uniform_int_distribution<std::size_t> pick(k, members.size() - 1);
      std::swap(members[k], members[pick(rng)]);
      centres.push_back(members[k]);
    }
  }
  if (centres.empty()) return out;
  std::shuffle(centres.begin(), centres.end(), rng);

  // Every region once (in parallel), on a grid of cells of the region radius: pass 1 takes the densities of
  // a sample of them, pass 2 decides their points.
  const RadiusGrid grid(pts, o.region_radius_m);
  std::vector<std::vector<std::uint32_t>> regions(centres.size());
  ParallelBlocks(centres.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) grid.Radius(pts[centres[k]], &regions[k]);
  });
  const double area = std::numbers::pi * o.region_radius_m * o.region_radius_m;

  // D̄ per group: mean candidate density over the regions of at most density_samples of the centres (the
  // first ones of the shuffled list, i.e. a uniform sample).
  {
    std::array<std::size_t, kNumGroups> taken{};
    for (std::size_t k = 0; k < centres.size(); ++k) {
      const GroupId g = in.groups[centres[k]];
      if (o.density_samples != 0 && taken[g] >= static_cast<std::size_t>(o.density_samples)) continue;
      ++taken[g];
      std::size_t candidates = 0;
      for (auto j : regions[k]) candidates += in.IsCandidate(j) ? 1 : 0;
      out.batch_densities.sum[g] += static_cast<double>(candidates) / area;
      out.batch_densities.count[g] += 1;
    }
  }
  DensitySums all = in.prior_densities;
  all.Add(out.batch_densities);

  // Pass 2 (sequential, in the shuffled order): each undecided candidate of the region's group is decided.
  std::vector<std::uint8_t> decided(in.size(), 0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::Vector2d> xy;
  std::vector<int> positive;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const std::uint32_t c = centres[k];
    const GroupId g = in.groups[c];
    const Plane& plane = planes.plane[g];
    const double mean = all.Mean(g);
    if (mean <= 0.0) continue;
    const std::vector<std::uint32_t>& region = regions[k];
    std::size_t other = 0;
    for (auto j : region) other += in.labels[j] != in.labels[c] ? 1 : 0;
    const double other_share = static_cast<double>(other) / static_cast<double>(region.size());
    const double d_norm = (static_cast<double>(region.size()) / area) / mean;
    const Eigen::Vector2d mu = plane.Project(pts[c]);

    std::optional<Boundary> boundary;
    if (use_boundary && !PsUsesInterior(other_share, o.ps_boundary_share)) {
      xy.clear();
      positive.clear();
      // At most ps_svm_max_samples training points, evenly strided over the region (deterministic).
      const std::size_t stride = (region.size() + static_cast<std::size_t>(o.ps_svm_max_samples) - 1) /
                                 static_cast<std::size_t>(o.ps_svm_max_samples);
      for (std::size_t r = 0; r < region.size(); r += stride) {
        const auto j = region[r];
        xy.push_back(plane.Project(pts[j]) - mu);
        positive.push_back(in.labels[j] == in.labels[c] ? 1 : 0);
      }
      boundary = FitBoundary(xy, positive, o.region_radius_m, o.ps_svm_c);
    }
    auto conservation = [&](std::uint32_t j) {
      const Eigen::Vector2d x = plane.Project(pts[j]) - mu;
      return boundary
                 ? PsBoundaryProbability(boundary->normal.dot(x) + boundary->offset, o.ps_boundary_sigma_m)
                 : PsInteriorProbability(x.squaredNorm(), d_norm, o.ps_interior_sigma_m);
    };
    // Streaming gate (1 in batch mode): the decided points of the group in the region count against what
    // the region would keep of its candidates, P_c' = P_c · max(0, 1 − decided / Σ P_c(candidates)).
    double gate = 1.0;
    if (in.num_fixed > 0) {
      std::size_t decided_points = 0;
      double expected_kept = 0.0;
      for (auto j : region) {
        if (in.groups[j] != g) continue;
        if (in.IsCandidate(j)) {
          expected_kept += conservation(j);
        } else {
          ++decided_points;
        }
      }
      gate = expected_kept > 0.0 ? std::max(0.0, 1.0 - static_cast<double>(decided_points) / expected_kept)
                                 : 0.0;
    }
    for (auto j : region) {
      if (in.groups[j] != g || !in.IsCandidate(j) || decided[j]) continue;
      decided[j] = 1;
      if (uniform(rng) > gate * conservation(j)) out.removed[j] = 1;
    }
  }
  return out;
}

}  // namespace semap::simplify
