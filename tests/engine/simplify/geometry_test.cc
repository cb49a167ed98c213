#include "engine/simplify/internal/geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace semap::simplify {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> p(n);
  for (auto& x : p) x = {u(rng), u(rng), u(rng)};
  return p;
}

TEST(PointIndex, RadiusAndKnnMatchBruteForce) {
  const auto pts = RandomPoints(2000, 1);
  const PointIndex index(pts);
  const Eigen::Vector3d q(0.1, -0.2, 0.3);
  std::vector<std::uint32_t> got;
  index.Radius(q, 0.25, &got);
  std::sort(got.begin(), got.end());
  std::vector<std::uint32_t> want;
  for (std::uint32_t i = 0; i < pts.size(); ++i) {
    if ((pts[i] - q).norm() <= 0.25) want.push_back(i);
  }
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());

  index.Knn(q, 10, &got);
  std::vector<std::uint32_t> order(pts.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](auto a, auto b) { return (pts[a] - q).norm() < (pts[b] - q).norm(); });
  order.resize(10);
  EXPECT_EQ(got, order);
}

TEST(RadiusGrid, RadiusMatchesBruteForce) {
  // Negative and positive coordinates, queries inside and outside the cloud, on and off cell corners.
  const auto pts = RandomPoints(3000, 2);
  const RadiusGrid grid(pts, 0.25);
  const std::vector<Eigen::Vector3d> queries = {{0.1, -0.2, 0.3},   {0.0, 0.0, 0.0}, {-0.75, 0.5, -0.25},
                                                {0.99, 0.99, 0.99}, {3.0, 3.0, 3.0}, pts[17]};
  for (const auto& q : queries) {
    std::vector<std::uint32_t> got, again;
    grid.Radius(q, &got);
    grid.Radius(q, &again);
    EXPECT_EQ(got, again);  // the same order every time
    std::sort(got.begin(), got.end());
    std::vector<std::uint32_t> want;
    for (std::uint32_t i = 0; i < pts.size(); ++i) {
      if ((pts[i] - q).norm() <= 0.25) want.push_back(i);
    }
    EXPECT_EQ(got, want) << q.transpose();
  }
  std::vector<std::uint32_t> none;
  const std::vector<Eigen::Vector3d> empty;
  RadiusGrid(empty, 0.25).Radius({0, 0, 0}, &none);
  EXPECT_TRUE(none.empty());
}

TEST(Geometry, OrientTowardsFacesTheViewpoint) {
  const Eigen::Vector3d n(0, 0, 1);
  EXPECT_EQ(OrientTowards(n, {0, 0, 0}, {1, 2, 3}), n);
  EXPECT_EQ(OrientTowards(n, {0, 0, 0}, {1, 2, -3}), -n);
}

}  // namespace
}  // namespace semap::simplify
