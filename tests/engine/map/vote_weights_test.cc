#include "engine/map/internal/vote_weights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace semap::map_internal {
namespace {

TEST(VoteWeights, GaussianComplementShape) {
  EXPECT_EQ(GaussianComplement(0.0, 0.05), 0.0);
  EXPECT_NEAR(GaussianComplement(0.05, 0.05), 1.0 - std::exp(-0.5), 1e-15);
  EXPECT_GT(GaussianComplement(0.2, 0.05), 0.999);
}

// The table against the library's erfc, densely and at random, and the properties the votes rely on.
TEST(VoteWeights, StandardNormalCdfMatchesErfc) {
  const auto reference = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  double worst = 0.0;
  for (double x = -12.0; x <= 12.0; x += 1e-3)
    worst = std::max(worst, std::abs(StandardNormalCdf(x) - reference(x)));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> anywhere(-kNormalCdfLimit, kNormalCdfLimit);
  for (int i = 0; i < 100000; ++i) {
    const double x = anywhere(rng);
    worst = std::max(worst, std::abs(StandardNormalCdf(x) - reference(x)));
  }
  EXPECT_LT(worst, 2e-9);
  EXPECT_EQ(StandardNormalCdf(0.0), 0.5);
  EXPECT_EQ(StandardNormalCdf(-kNormalCdfLimit), 0.0);
  EXPECT_EQ(StandardNormalCdf(kNormalCdfLimit), 1.0);
  EXPECT_EQ(StandardNormalCdf(-1e300), 0.0);
  EXPECT_EQ(StandardNormalCdf(1e300), 1.0);
  // Monotone, as a distribution function (a free vote never falls as a sample moves away from the point), up
  // to the rounding of the interpolation's sum (a few units in the last place of 1).
  constexpr double kRounding = 1e-15;
  double previous = 0.0;
  for (double x = -kNormalCdfLimit - 0.01; x <= kNormalCdfLimit + 0.01; x += 1e-4) {
    const double value = StandardNormalCdf(x);
    ASSERT_GE(value, previous - kRounding) << "at " << x;
    previous = value;
  }
}

TEST(VoteWeights, SaturationGivesTheFullFixedPointWeight) {
  for (double sigma : {0.01, 0.05, 0.3}) {
    const double d = SaturationDistance(sigma);
    EXPECT_EQ(QuantiseWeight(GaussianComplement(d, sigma)), std::int64_t(kVoteScale));
    EXPECT_EQ(QuantiseWeight(GaussianComplement(10.0 * d, sigma)), std::int64_t(kVoteScale));
    EXPECT_LT(QuantiseWeight(GaussianComplement(0.5 * d, sigma)), std::int64_t(kVoteScale));
  }
}

// The closest-point regions against brute-force sampling of the triangle.
TEST(VoteWeights, PointTriangleDistanceMatchesSampling) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p = 2.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    double best = 1e9;
    const int n = 200;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        best = std::min(best, (p - q).norm());
      }
    const double d = PointTriangleDistance(p, a, b, c);
    EXPECT_LE(d, best + 1e-12);
    EXPECT_GT(d, best - 0.02) << "trial " << trial;
  }
}

TEST(VoteWeights, DistanceSkipsFacetsThroughTheTarget) {
  Delaunay dt;
  const VertexHandle target = dt.insert(Point(0, 0, 0));
  dt.insert(Point(1, 0, 0));
  dt.insert(Point(0, 1, 0));
  dt.insert(Point(0, 0, 1));
  const CellHandle cell = dt.finite_cells_begin();
  // The only facet not through the target is x + y + z = 1, at 1/sqrt(3) from the origin.
  EXPECT_NEAR(DistanceToClosestFacet(cell, target, 1e9), 1.0 / std::sqrt(3.0), 1e-12);
}

}  // namespace
}  // namespace semap::map_internal
