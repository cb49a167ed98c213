#include "engine/simplify/conservation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semap::simplify {
namespace {

TEST(Conservation, LinearMatchesHandValues) {
  // c = c̄ − (d̃ − 1) / c̄ with c̄ = 0.4.
  EXPECT_DOUBLE_EQ(LinearConservation(1.0, 0.4), 0.4);           // c(D̄) = c̄
  EXPECT_NEAR(LinearConservation(1.1, 0.4), 0.4 - 0.25, 1e-12);  // 0.15
  EXPECT_NEAR(LinearConservation(0.9, 0.4), 0.4 + 0.25, 1e-12);  // 0.65
  EXPECT_DOUBLE_EQ(LinearConservation(0.5, 0.4), 1.0);           // clamped high
  EXPECT_DOUBLE_EQ(LinearConservation(2.0, 0.4), 0.0);           // clamped low
  EXPECT_DOUBLE_EQ(LinearConservation(2.0, 0.4, 0.1), 0.1);      // min_conservation
  EXPECT_DOUBLE_EQ(LinearConservation(1.0, 0.5), 0.5);
}

TEST(Conservation, LinearFallsWithDensity) {
  double previous = 2.0;
  for (double d = 0.77; d <= 1.15; d += 0.01) {  // inside the unclamped range [0.76, 1.16]
    const double c = LinearConservation(d, 0.4);
    EXPECT_LT(c, previous) << "d̃ = " << d;
    previous = c;
  }
}

TEST(Conservation, AdaptiveFunctionMatchesHandValues) {
  EXPECT_DOUBLE_EQ(AdaptiveF(0.0, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(AdaptiveF(1.0, 1.0), 0.75);  // 0.5 + 1 / (2·2)
  EXPECT_DOUBLE_EQ(AdaptiveF(-1.0, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(AdaptiveF(2.0, 0.5), 0.75);  // 0.5 + 1 / (2·2)
  EXPECT_NEAR(AdaptiveF(1e9, 1.0), 1.0, 1e-8);
  for (double c : {0.1, 0.4, 0.5, 0.77}) EXPECT_NEAR(AdaptiveF(AdaptiveFInverse(c, 2.0), 2.0), c, 1e-12);
  // c̄ = 0.4, w = 1: f⁻¹(0.4) = −0.2 / 0.8 = −0.25, τ = 0.75.
  EXPECT_NEAR(AdaptiveTau(0.4, 1.0), 0.75, 1e-12);
}

TEST(Conservation, AdaptiveMatchesHandValuesAndTarget) {
  EXPECT_NEAR(AdaptiveConservation(1.0, 0.4, 1.0), 0.4, 1e-12);  // c(D̄) = c̄
  EXPECT_NEAR(AdaptiveConservation(1.0, 0.5, 3.0), 0.5, 1e-12);
  EXPECT_NEAR(AdaptiveConservation(2.0, 0.4, 1.0), 0.5 - 1.25 / 4.5, 1e-12);  // f(−1.25)
  EXPECT_NEAR(AdaptiveConservation(0.0, 0.4, 1.0), 0.5 + 0.75 / 3.5, 1e-12);  // f(0.75)
  double previous = 2.0;
  for (double d = 0.0; d < 5.0; d += 0.1) {
    const double c = AdaptiveConservation(d, 0.4, 1.0);
    EXPECT_LT(c, previous);
    EXPECT_GT(c, 0.0);
    previous = c;
  }
}

TEST(Conservation, AdaptiveClassIsNeverBelowAdaptive) {
  EXPECT_NEAR(AdaptiveClassConservation(1.0, 0.5, 0.4, 1.0), 0.6, 1e-12);  // 1.5 · 0.4
  EXPECT_DOUBLE_EQ(AdaptiveClassConservation(0.0, 0.5, 0.4, 1.0), 1.0);    // saturated
  EXPECT_NEAR(AdaptiveClassConservation(1.7, 0.0, 0.4, 1.0), AdaptiveConservation(1.7, 0.4, 1.0), 1e-12);
  for (double d = 0.0; d < 4.0; d += 0.25) {
    for (double p = 0.0; p <= 1.0; p += 0.1) {
      EXPECT_GE(AdaptiveClassConservation(d, p, 0.4, 1.0), AdaptiveConservation(d, 0.4, 1.0));
    }
  }
}

TEST(Conservation, DiscardCount) {
  EXPECT_EQ(DiscardCount(0.4, 10), 6u);
  EXPECT_EQ(DiscardCount(0.4, 7), 4u);  // floor(4.2)
  EXPECT_EQ(DiscardCount(1.0, 5), 0u);
  EXPECT_EQ(DiscardCount(0.0, 5), 5u);
  EXPECT_EQ(DiscardCount(0.5, 0), 0u);
}

TEST(Conservation, ProbabilisticTerms) {
  EXPECT_TRUE(PsUsesInterior(0.05, 0.1));
  EXPECT_FALSE(PsUsesInterior(0.1, 0.1));
  EXPECT_DOUBLE_EQ(PsInteriorProbability(0.0, 1.0, 0.2), 0.0);  // centre: always removed
  // |x − μ|² = 2 d̃ σ² ⇒ 1 − e⁻¹.
  EXPECT_NEAR(PsInteriorProbability(0.16, 2.0, 0.2), 1.0 - std::exp(-1.0), 1e-12);
  EXPECT_NEAR(PsInteriorProbability(0.08, 1.0, 0.2), 1.0 - std::exp(-1.0), 1e-12);
  // Denser region (d̃ > 1): wider Gaussian, lower conservation at the same distance.
  EXPECT_LT(PsInteriorProbability(0.04, 3.0, 0.2), PsInteriorProbability(0.04, 1.0, 0.2));
  EXPECT_DOUBLE_EQ(PsBoundaryProbability(0.0, 0.1), 1.0);
  EXPECT_NEAR(PsBoundaryProbability(0.1, 0.1), std::exp(-0.5), 1e-12);
  EXPECT_NEAR(PsBoundaryProbability(-0.2, 0.1), std::exp(-2.0), 1e-12);
}

}  // namespace
}  // namespace semap::simplify
