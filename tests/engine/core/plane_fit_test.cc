#include "engine/core/plane_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace semap {
namespace {

TEST(PlaneFit, PcaOfAPlaneAndALine) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) pts.push_back({i * 0.1, j * 0.1, 2.0});
  }
  std::vector<std::uint32_t> all(pts.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  const PcaResult r = Pca(pts, all);
  ASSERT_TRUE(r.valid);
  EXPECT_NEAR(std::abs(r.normal.z()), 1.0, 1e-9);
  EXPECT_NEAR(r.surface_variation, 0.0, 1e-12);
  // The vertices of a regular tetrahedron are isotropic: variation 1/3.
  const std::vector<Eigen::Vector3d> cube = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  EXPECT_NEAR(Pca(cube, {0, 1, 2, 3}).surface_variation, 1.0 / 3.0, 1e-9);
  EXPECT_FALSE(Pca(pts, {0, 1}).valid);
}

TEST(PlaneFit, RansacFindsThePlaneDespiteOutliers) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Eigen::Vector3d> pts;
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
  const Plane truth = Plane::FromPointNormal({0, 0, 1.5}, n);
  for (int i = 0; i < 3000; ++i) {
    Eigen::Vector3d p(u(rng), u(rng), 0.0);
    p.z() = (-truth.offset - n.x() * p.x() - n.y() * p.y()) / n.z() + noise(rng);
    pts.push_back(p);
  }
  for (int i = 0; i < 1500; ++i) pts.push_back({u(rng), u(rng), u(rng)});  // 33 % outliers
  std::vector<std::uint32_t> all(pts.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  std::mt19937_64 ransac_rng(9);
  const auto plane = FitPlaneRansac(pts, all, 0.03, 200, 2000, /*confidence=*/1.0, ransac_rng);
  ASSERT_TRUE(plane.has_value());
  EXPECT_GT(std::abs(plane->normal.dot(n)), 0.9999);
  EXPECT_NEAR(std::abs(plane->SignedDistance({0, 0, 1.5})), 0.0, 0.01);
  // Frame is orthonormal.
  EXPECT_NEAR(plane->u.dot(plane->v), 0.0, 1e-12);
  EXPECT_NEAR(plane->u.dot(plane->normal), 0.0, 1e-12);
  EXPECT_NEAR(plane->u.norm(), 1.0, 1e-12);
  std::vector<std::uint32_t> two = {0, 1};
  EXPECT_FALSE(FitPlaneRansac(pts, two, 0.03, 10, 10, 1.0, ransac_rng).has_value());

  // The adaptive stop (confidence < 1) against the exhaustive search as reference: the same plane.
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    std::mt19937_64 adaptive_rng(seed);
    const auto adaptive = FitPlaneRansac(pts, all, 0.03, 200, 2000, 0.999, adaptive_rng);
    ASSERT_TRUE(adaptive.has_value());
    EXPECT_GT(std::abs(adaptive->normal.dot(plane->normal)), 0.9999) << "seed " << seed;
    EXPECT_NEAR(std::abs(adaptive->SignedDistance({0, 0, 1.5})), 0.0, 0.01) << "seed " << seed;
  }
}

TEST(PlaneFit, RansacIterationsNeededMatchesHandValues) {
  // ceil(log(1 - p) / log(1 - w³)).
  EXPECT_EQ(RansacIterationsNeeded(0.5, 0.99, 200), 35);    // log 0.01 / log 0.875 = 34.49
  EXPECT_EQ(RansacIterationsNeeded(0.8, 0.999, 200), 10);   // log 0.001 / log 0.488 = 9.64
  EXPECT_EQ(RansacIterationsNeeded(0.1, 0.999, 200), 200);  // 6905, clamped
  EXPECT_EQ(RansacIterationsNeeded(1.0, 0.999, 200), 1);
  EXPECT_EQ(RansacIterationsNeeded(0.0, 0.999, 200), 200);
  EXPECT_EQ(RansacIterationsNeeded(0.5, 1.0, 200), 200);  // confidence 1: exhaustive
}

}  // namespace
}  // namespace semap
