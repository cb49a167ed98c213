#include "engine/simplify/conservation.h"

#include <algorithm>
#include <cmath>

#include "engine/core/check.h"

namespace semap::simplify {

namespace {
double Clamp(double c, double min_c) { return std::clamp(c, min_c, 1.0); }
}  // namespace

double NormalisedDensity(double density, double mean_density) {
  SEMAP_ASSERT(mean_density > 0.0, "mean density " << mean_density);
  return density / mean_density;
}

double LinearConservation(double normalised_density, double target, double min_conservation) {
  SEMAP_ASSERT(target > 0.0 && target <= 1.0);
  return Clamp(target - (normalised_density - 1.0) / target, min_conservation);
}

double AdaptiveF(double x, double stretch) {
  return 0.5 + stretch * x / (2.0 * (1.0 + stretch * std::abs(x)));
}

double AdaptiveFInverse(double c, double stretch) {
  SEMAP_ASSERT(c > 0.0 && c < 1.0 && stretch > 0.0, "c " << c << " w " << stretch);
  // f(x) − 0.5 = g / 2 with g = 2c − 1 ∈ (−1, 1):  w x = g (1 + w |x|)  ⇒  x = g / (w (1 − |g|)).
  const double g = 2.0 * c - 1.0;
  return g / (stretch * (1.0 - std::abs(g)));
}

double AdaptiveTau(double target, double stretch) { return 1.0 + AdaptiveFInverse(target, stretch); }

double AdaptiveConservation(double normalised_density, double target, double stretch,
                            double min_conservation) {
  const double tau = AdaptiveTau(target, stretch);
  return Clamp(AdaptiveF(tau - normalised_density, stretch), min_conservation);
}

double AdaptiveClassConservation(double normalised_density, double other_share, double target, double stretch,
                                 double min_conservation) {
  const double tau = AdaptiveTau(target, stretch);
  return Clamp(std::min(1.0, (1.0 + other_share) * AdaptiveF(tau - normalised_density, stretch)),
               min_conservation);
}

std::size_t DiscardCount(double conservation, std::size_t n) {
  const double c = std::clamp(conservation, 0.0, 1.0);
  // The small epsilon absorbs rounding in (1 − c)·n for exact products such as 0.6 · 10.
  return std::min(n, static_cast<std::size_t>(std::floor((1.0 - c) * static_cast<double>(n) + 1e-9)));
}

bool PsUsesInterior(double other_share, double threshold) { return other_share < threshold; }

double PsInteriorProbability(double squared_distance_m2, double normalised_density, double sigma_m) {
  SEMAP_ASSERT(normalised_density > 0.0 && sigma_m > 0.0);
  return 1.0 - std::exp(-squared_distance_m2 / (2.0 * normalised_density * sigma_m * sigma_m));
}

double PsBoundaryProbability(double distance_m, double sigma_m) {
  SEMAP_ASSERT(sigma_m > 0.0);
  return std::exp(-distance_m * distance_m / (2.0 * sigma_m * sigma_m));
}

}  // namespace semap::simplify
