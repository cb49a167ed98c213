// The formulas of the paper's simplification methods, as pure functions (hand-checked in the tests).
//
// Densities: D is a region's density (points per m²), D̄ the mean region density of the class group. Every
// formula below uses the *normalised* density d̃ = D / D̄ (dimensionless), which is how we read the paper's
// equations whose dimensions do not match as printed (see each function). Thread-safe (pure functions).
#pragma once

#include <cstddef>

namespace semap::simplify {

// d̃ = D / D̄; D̄ must be > 0.
double NormalisedDensity(double density, double mean_density);

// LS (paper eq. "linear decimation"): c = −(D̄ / c̄)(D − D̄) + c̄, printed with D̄·D, whose units do not
// match c. Our reading: the equation is written in units of D̄ (D̄ = 1, D = d̃), so
//     c = c̄ − (d̃ − 1) / c̄,        clamped to [min_c, 1].
// Hence c(D̄) = c̄, c falls with D (slope −1/c̄ per D̄), c = 1 at d̃ = 1 − c̄(1 − c̄), c = 0 at d̃ = 1 + c̄².
double LinearConservation(double normalised_density, double target, double min_conservation = 0.0);

// AS: f(x) = 0.5 + w x / (2 (1 + w |x|)), increasing, f(0) = 0.5, f(±∞) = 1 / 0.
double AdaptiveF(double x, double stretch);
// Inverse of f on (0, 1): the x with f(x) = c.
double AdaptiveFInverse(double c, double stretch);
// AS's τ in units of D̄, chosen so that the conservation at d̃ = 1 (D = D̄) is c̄. See AdaptiveConservation.
double AdaptiveTau(double target, double stretch);
// AS: the paper writes c = f(D − τ) with f increasing, which would keep a larger share of the points in
// denser regions, contrary to LS and to the stated aim (simplify more where the density is above average).
// Our reading keeps f and the τ condition but makes c fall with the density, like LS:
//     c = f(τ − d̃),   τ = 1 + f⁻¹(c̄)   so that c(D̄) = c̄,   clamped to [min_c, 1].
double AdaptiveConservation(double normalised_density, double target, double stretch,
                            double min_conservation = 0.0);
// ACS: c = min(1, (1 + p̃) · f(τ − d̃)), p̃ ∈ [0, 1] the share of points of other labels in the region.
// Always ≥ AdaptiveConservation for the same region.
double AdaptiveClassConservation(double normalised_density, double other_share, double target, double stretch,
                                 double min_conservation = 0.0);

// Points to discard from a region of n points with conservation c: floor((1 − c) · n) (a fraction of a
// point is never discarded), so that ceil(c · n) points remain (up to rounding of c · n).
std::size_t DiscardCount(double conservation, std::size_t n);

// PS: i(p̃) = 1 when p̃ < threshold (interior region, use P_I), else 0 (boundary region, use P_B).
bool PsUsesInterior(double other_share, double threshold);
// PS interior term: P_I = 1 − N(μ, Σ) with Σ = diag(d̃σ², d̃σ²), the Gaussian normalised to peak 1 so that
// P_I ∈ [0, 1) with P_I = 0 at the region centre μ:  P_I = 1 − exp(−|x − μ|² / (2 d̃ σ²)).
// `squared_distance_m2` is |x − μ|² measured on the class plane.
double PsInteriorProbability(double squared_distance_m2, double normalised_density, double sigma_m);
// PS boundary term: P_B = exp(−d² / (2 σ²)), d the distance on the plane to the SVM class boundary.
double PsBoundaryProbability(double distance_m, double sigma_m);

}  // namespace semap::simplify
