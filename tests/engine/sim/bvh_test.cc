#include "engine/sim/bvh.h"

#include <gtest/gtest.h>

#include "engine/sim/internal/random.h"

namespace semap::sim {
namespace {

// Brute-force nearest hit (Möller-Trumbore over every triangle).
std::optional<RayHit> BruteForce(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                 double t_max) {
  std::optional<RayHit> best;
  for (std::uint32_t k = 0; k < s.triangles.size(); ++k) {
    const Eigen::Vector3d a = s.vertices[s.triangles[k][0]];
    const Eigen::Vector3d e1 = s.vertices[s.triangles[k][1]] - a, e2 = s.vertices[s.triangles[k][2]] - a;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-18) continue;
    const Eigen::Vector3d sv = o - a;
    const double u = sv.dot(p) / det;
    const Eigen::Vector3d q = sv.cross(e1);
    const double v = d.dot(q) / det, t = e2.dot(q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t < 0 || t > t_max) continue;
    if (!best || t < best->t) best = RayHit{t, k};
  }
  return best;
}

Scene RandomTriangles(int n, std::uint64_t seed) {
  sim_internal::Rng rng(seed);
  Scene s;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d c(rng.Uniform(-20, 20), rng.Uniform(-20, 20), rng.Uniform(-5, 5));
    for (int v = 0; v < 3; ++v) {
      s.vertices.push_back(
          c + Eigen::Vector3d(rng.Uniform(-1.5, 1.5), rng.Uniform(-1.5, 1.5), rng.Uniform(-1.5, 1.5)));
    }
    s.triangles.push_back({3u * k, 3u * k + 1, 3u * k + 2});
  }
  return s;
}

TEST(TriangleBvh, AgreesWithBruteForce) {
  const Scene s = RandomTriangles(3000, 5);
  const TriangleBvh bvh(s);
  EXPECT_GT(bvh.num_nodes(), 1u);
  sim_internal::Rng rng(9);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d o(rng.Uniform(-30, 30), rng.Uniform(-30, 30), rng.Uniform(-10, 10));
    const Eigen::Vector3d d =
        Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()) * rng.Uniform(0.5, 2.0);
    const auto expected = BruteForce(s, o, d, 100.0);
    const auto got = bvh.Intersect(o, d, 0.0, 100.0);
    ASSERT_EQ(expected.has_value(), got.has_value()) << "ray " << k;
    if (expected) {
      ++hits;
      EXPECT_NEAR(got->t, expected->t, 1e-9);
      EXPECT_EQ(got->triangle, expected->triangle);
    }
  }
  EXPECT_GT(hits, 200);  // the test exercises hits, not only misses
}

TEST(TriangleBvh, AxisAlignedRaysAndRangeLimits) {
  Scene s;
  s.vertices = {{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}};
  s.triangles = {{0, 1, 2}};
  const TriangleBvh bvh(s);
  const auto hit = bvh.Intersect({0, 0, 0}, {0, 0, 1}, 0.0, 100.0);
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->t, 5.0);
  EXPECT_FALSE(bvh.Intersect({0, 0, 0}, {0, 0, 1}, 0.0, 4.9));
  EXPECT_FALSE(bvh.Intersect({0, 0, 0}, {0, 0, 1}, 5.1, 100.0));
  EXPECT_FALSE(bvh.Intersect({0, 0, 0}, {0, 0, -1}, 0.0, 100.0));
  EXPECT_FALSE(TriangleBvh(Scene{}).Intersect({0, 0, 0}, {0, 0, 1}, 0.0, 1.0));
}

}  // namespace
}  // namespace semap::sim
