// The visibility vote weights and their fixed-point form.
//
// Interpretation of the paper's formula (its text reads 1 - e^{d^2 / 2σ}, a typo): a ray camera → p adds
//   w_free   = 1 - exp(-d^2 / (2 σ_free^2))    to each cell it crosses before p,
//   w_matter = 1 - exp(-d^2 / (2 σ_matter^2))  to each cell crossed by its extension behind p,
// where d is the Euclidean distance from p to the closest facet of the crossed cell. Facets that contain p
// itself are left out of that minimum: they are at distance 0 for every cell incident to p, which would zero
// the weight of every cell touching p whatever its size (and the matter extension, which starts in cells
// incident to p, would then almost never vote). So for a cell incident to p, d is the distance from p to the
// opposite facet.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>

#include "engine/map/internal/triangulation.h"
#include "engine/map/map_types.h"

namespace semap::map_internal {

inline constexpr double kVoteScale = kVoteFixedScale;  // fixed-point units per unit weight

inline std::int64_t QuantiseWeight(double w) { return std::llround(w * kVoteScale); }
inline double DequantiseVote(std::int64_t q) { return double(q) / kVoteScale; }

inline double GaussianComplement(double d_m, double sigma_m) {
  return 1.0 - std::exp(-(d_m * d_m) / (2.0 * sigma_m * sigma_m));
}

// Φ(x), the standard normal distribution function, within 2e-9 of 0.5·erfc(−x/√2) everywhere: cubic Hermite
// interpolation in a table of Φ and its density at steps of 1/32 over ±kNormalCdfLimit, 0 below and 1 above
// (Φ(−8.5) is 1e-17). std::erfc in the depth votes took ~9 % of the map's CPU (KITTI 04, half resolution,
// perf; bench/results/frame-rate.md, "the normal distribution function of the depth votes from a table");
// this is a few multiplications. Thread-safe (the table is built once, on first use).
inline constexpr double kNormalCdfLimit = 8.5;
double StandardNormalCdf(double x);

// Distance from p to triangle abc (closest-point regions, Ericson, Real-Time Collision Detection 5.1.5).
double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// The distance beyond which the fixed-point weight with this σ is exactly kVoteScale (the Gaussian term is
// below a quarter of a fixed-point unit, so rounding gives the full weight whatever the exact distance).
inline double SaturationDistance(double sigma_m) {
  return sigma_m * std::sqrt(2.0 * std::log(4.0 * kVoteScale));
}

// d of the weights above for the ray to vertex `target` and the finite cell `cell`, or some value
// ≥ saturation_m when d ≥ saturation_m (then the fixed-point weight is the same): for a cell not incident to
// the target, the distance from the target to the cell's bounding box is a lower bound of d and is returned
// when it reaches saturation_m. The cell's vertices are taken in lexicographic order of their coordinates so
// that the result does not depend on CGAL's vertex order inside the cell (the same cell in two triangulations
// gives bit-identical distances).
double DistanceToClosestFacet(CellHandle cell, VertexHandle target, double saturation_m);

}  // namespace semap::map_internal
