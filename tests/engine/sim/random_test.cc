#include "engine/sim/internal/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semap::sim::sim_internal {
namespace {

TEST(Random, NormalsHaveUnitVarianceAndAreDeterministic) {
  Rng a(1), b(1);
  double s1 = 0, s2 = 0, f1 = 0, f2 = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double x = a.Normal(), y = a.FastNormal();
    s1 += x, s2 += x * x, f1 += y, f2 += y * y;
    ASSERT_EQ(x, b.Normal());
    ASSERT_EQ(y, b.FastNormal());
  }
  EXPECT_NEAR(s1 / n, 0.0, 0.01);
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
  EXPECT_NEAR(f1 / n, 0.0, 0.01);
  EXPECT_NEAR(f2 / n, 1.0, 0.01);
}

TEST(Random, NoiseIsInRangeAndFadesToItsMean) {
  for (int k = 0; k < 1000; ++k) {
    const float v = ValueNoise(k * 0.37, k * 0.11, -k * 0.07, 5);
    EXPECT_GE(v, 0.0f);
    EXPECT_LT(v, 1.0f);
  }
  // A pixel footprint far larger than every octave's wavelength gives the mean, 0.5.
  EXPECT_FLOAT_EQ(Fbm(1.3, 2.4, 3.5, 0.1, 3, 10.0, 9), 0.5f);
  EXPECT_NE(Fbm(1.3, 2.4, 3.5, 0.1, 3, 0.001, 9), 0.5f);
}

}  // namespace
}  // namespace semap::sim::sim_internal
