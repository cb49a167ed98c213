#include "engine/eval/surface_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

// The square [x0, x1] × [0, 10] at height z, as two triangles.
Mesh Square(double x0, double x1, double z) {
  Mesh m;
  m.vertices = {{x0, 0, z}, {x1, 0, z}, {x1, 10, z}, {x0, 10, z}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// A grid of samples on the truth square [0, 10]² at z = 0, cell centres.
std::vector<Eigen::Vector3d> TruthSamples() {
  std::vector<Eigen::Vector3d> s;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) s.emplace_back(0.25 + 0.5 * i, 0.25 + 0.5 * j, 0.0);
  }
  return s;
}

TEST(SurfaceMetrics, AnalyticPlanes) {
  const Mesh truth = Square(0, 10, 0);
  // Half of the plane, 0.1 m above it: every reconstruction sample is right, half the truth is covered.
  const SurfaceMetrics half = CompareSurfaces(Square(0, 5, 0.1), truth, TruthSamples());
  EXPECT_DOUBLE_EQ(half.accuracy, 1.0);
  EXPECT_NEAR(half.mean_distance_m, 0.1, 1e-12);
  EXPECT_NEAR(half.area_m2, 50.0, 1e-12);
  EXPECT_DOUBLE_EQ(half.vertex_accuracy, 1.0);
  EXPECT_NEAR(half.vertex_mean_distance_m, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(half.completeness, 0.5);
  EXPECT_EQ(half.vertex_samples, 4 + 2);
  EXPECT_EQ(half.area_samples, SurfaceMetricsOptions().area_samples);
  EXPECT_EQ(half.truth_samples, 400);
  // The truth samples beyond x = 5 are at sqrt(dx² + 0.1²) from the half plane.
  double expected = 0.0;
  for (const auto& p : TruthSamples()) {
    const double dx = std::max(0.0, p.x() - 5.0);
    expected += std::sqrt(dx * dx + 0.01) / 400.0;
  }
  EXPECT_NEAR(half.mean_completeness_m, expected, 1e-9);

  // The whole plane 0.3 m off: nothing within τ = 0.2 m, everything within τ = 0.5 m.
  const SurfaceMetrics off = CompareSurfaces(Square(0, 10, 0.3), truth, TruthSamples());
  EXPECT_DOUBLE_EQ(off.accuracy, 0.0);
  EXPECT_DOUBLE_EQ(off.vertex_accuracy, 0.0);
  EXPECT_DOUBLE_EQ(off.area_within_near, 1.0);
  EXPECT_DOUBLE_EQ(off.area_beyond_far, 0.0);
  EXPECT_DOUBLE_EQ(off.completeness, 0.0);
  SurfaceMetricsOptions loose;
  loose.threshold_m = 0.5;
  const SurfaceMetrics ok = CompareSurfaces(Square(0, 10, 0.3), truth, TruthSamples(), loose);
  EXPECT_DOUBLE_EQ(ok.accuracy, 1.0);
  EXPECT_DOUBLE_EQ(ok.completeness, 1.0);
}

// Appends triangle (a, b, c) to `m` as a separate piece.
void AddTriangle(Mesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {a, b, c});
  m.triangles.push_back({base, base + 1, base + 2});
}

// The truth for the by-area tests: the plane z = 0 over [-50, 50]², far wider than the reconstructions, so
// that a point's distance to it is its height.
Mesh GroundTruth() {
  Mesh m;
  AddTriangle(m, {-50, -50, 0}, {50, -50, 0}, {50, 50, 0});
  AddTriangle(m, {-50, -50, 0}, {50, 50, 0}, {-50, 50, 0});
  return m;
}

// Binomial standard error of a share p measured on n independent samples (stratified samples do better).
double ShareError(double p, int n) { return std::sqrt(p * (1.0 - p) / n); }

TEST(SurfaceMetrics, ByAreaAUnitSquareAndALidWeighByTheirArea) {
  // A unit square 0.1 m above the plane (accurate: 1 m²) and a lid 3 m above it (wrong: 9 m²).
  Mesh m;
  AddTriangle(m, {0, 0, 0.1}, {1, 0, 0.1}, {1, 1, 0.1});
  AddTriangle(m, {0, 0, 0.1}, {1, 1, 0.1}, {0, 1, 0.1});
  AddTriangle(m, {10, 0, 3}, {16, 0, 3}, {10, 3, 3});
  const SurfaceMetrics s = CompareSurfaces(m, GroundTruth(), {});
  const int n = SurfaceMetricsOptions().area_samples;
  EXPECT_NEAR(s.area_m2, 10.0, 1e-12);
  EXPECT_NEAR(s.accuracy, 0.1, 4 * ShareError(0.1, n));
  EXPECT_NEAR(s.area_within_near, 0.1, 4 * ShareError(0.1, n));
  EXPECT_NEAR(s.area_beyond_near, 0.9, 4 * ShareError(0.1, n));
  EXPECT_NEAR(s.area_beyond_far, 0.9, 4 * ShareError(0.1, n));
  EXPECT_NEAR(s.mean_distance_m, 0.1 * 0.1 + 0.9 * 3.0, 4 * 2.9 * ShareError(0.1, n));
  // One sample per vertex and centroid: the square's 6 + 2 are right, the lid's 3 + 1 wrong: 2/3 "accurate".
  EXPECT_EQ(s.vertex_samples, 9 + 3);
  EXPECT_DOUBLE_EQ(s.vertex_accuracy, 8.0 / 12.0);
}

TEST(SurfaceMetrics, ByAreaATinyRightTriangleCannotHideAHugeWrongOne) {
  Mesh m;
  AddTriangle(m, {0, 0, 0.05}, {0.1, 0, 0.05}, {0, 0.1, 0.05});  // 0.005 m², right
  AddTriangle(m, {-20, -20, 4}, {0, -20, 4}, {-20, 0, 4});       // 200 m², 4 m off
  const SurfaceMetrics s = CompareSurfaces(m, GroundTruth(), {});
  EXPECT_LT(s.accuracy, 0.001);
  EXPECT_GT(s.area_beyond_far, 0.999);
  EXPECT_NEAR(s.mean_distance_m, 4.0, 0.01);
  EXPECT_DOUBLE_EQ(s.vertex_accuracy, 0.5);  // what the per-vertex figure says about the same mesh
}

TEST(SurfaceMetrics, ByAreaOnASlopeMatchesTheUniformDistribution) {
  // A rectangle rising from z = 0 to z = 4 over x in [0, 10]: the distance is uniform on [0, 4] by area.
  Mesh m;
  AddTriangle(m, {0, 0, 0}, {10, 0, 4}, {10, 5, 4});
  AddTriangle(m, {0, 0, 0}, {10, 5, 4}, {0, 5, 0});
  SurfaceMetricsOptions options;
  options.seed = 7;
  const SurfaceMetrics s = CompareSurfaces(m, GroundTruth(), {}, options);
  const int n = options.area_samples;
  EXPECT_NEAR(s.area_m2, 5.0 * std::sqrt(116.0), 1e-9);
  EXPECT_NEAR(s.accuracy, 0.2 / 4.0, 4 * ShareError(0.05, n));
  EXPECT_NEAR(s.area_within_near, 0.5 / 4.0, 4 * ShareError(0.125, n));
  EXPECT_NEAR(s.area_beyond_far, 0.5, 4 * ShareError(0.5, n));
  EXPECT_NEAR(s.mean_distance_m, 2.0, 4 * 4.0 / std::sqrt(12.0 * n));
  // Another threshold and bins move the figures where the distribution says.
  options.threshold_m = 1.0;
  options.near_m = 2.0;
  options.far_m = 3.0;
  const SurfaceMetrics t = CompareSurfaces(m, GroundTruth(), {}, options);
  EXPECT_NEAR(t.accuracy, 0.25, 4 * ShareError(0.25, n));
  EXPECT_NEAR(t.area_within_near, 0.5, 4 * ShareError(0.5, n));
  EXPECT_NEAR(t.area_beyond_far, 0.25, 4 * ShareError(0.25, n));
}

TEST(SampleSurface, IsUniformByAreaInsideTheTrianglesAndDeterministic) {
  Mesh m;
  AddTriangle(m, {0, 0, 0}, {1, 0, 0}, {0, 2, 0});  // 1 m², in the plane z = 0
  AddTriangle(m, {0, 0, 5}, {3, 0, 5}, {0, 2, 5});  // 3 m², in the plane z = 5
  AddTriangle(m, {0, 0, 9}, {1, 0, 9}, {2, 0, 9});  // degenerate: no area, never sampled
  const std::vector<Eigen::Vector3d> a = SampleSurface(m, 1000, 3);
  ASSERT_EQ(a.size(), 1000u);
  int upper = 0;
  double below_half = 0;  // samples of the upper triangle with y < 1: 3/4 of its area
  for (const Eigen::Vector3d& p : a) {
    const bool on_upper = p.z() > 2.5;
    EXPECT_NEAR(p.z(), on_upper ? 5.0 : 0.0, 1e-12);
    const double width = on_upper ? 3.0 : 1.0;  // the triangle is x >= 0, y >= 0, x / width + y / 2 <= 1
    EXPECT_GE(p.x(), -1e-12);
    EXPECT_GE(p.y(), -1e-12);
    EXPECT_LE(p.x() / width + p.y() / 2.0, 1.0 + 1e-12);
    if (on_upper) {
      ++upper;
      below_half += p.y() < 1.0 ? 1 : 0;
    }
  }
  // Stratified by cumulative area: the 3 m² triangle gets 750 samples, give or take the one straddling.
  EXPECT_NEAR(upper, 750, 1);
  EXPECT_NEAR(below_half / upper, 0.75, 4 * ShareError(0.75, upper));
  const std::vector<Eigen::Vector3d> b = SampleSurface(m, 1000, 3);
  EXPECT_EQ(a, b);
  EXPECT_NE(SampleSurface(m, 1000, 4), a);
  EXPECT_TRUE(SampleSurface(Mesh(), 10, 1).empty());
  EXPECT_NEAR(SurfaceArea(m), 4.0, 1e-12);
}

// Each truth sample's depth is its y (a camera at y = 0 looking along +y): the reconstruction covers x < 5,
// so every band holds half covered samples, except where the depths put only covered or uncovered ones.
TEST(SurfaceMetrics, CompletenessByDepthSplitsTheSamplesByTheDepthTheyWereSeenAt) {
  const Mesh truth = Square(0, 10, 0);
  const std::vector<Eigen::Vector3d> samples = TruthSamples();
  std::vector<double> depths;
  for (const auto& p : samples)
    depths.push_back(p.x() < 5.0 ? 2.0 * p.y() : 25.0 + p.y());  // 0-20 m / 25-35 m
  SurfaceMetricsOptions options;
  options.completeness_depth_edges_m = {10.0, 30.0};
  const SurfaceMetrics s = CompareSurfaces(Square(0, 5, 0.1), truth, samples, options, depths);
  ASSERT_EQ(s.completeness_by_depth.size(), 3u);
  const auto& near = s.completeness_by_depth[0];
  const auto& mid = s.completeness_by_depth[1];
  const auto& far = s.completeness_by_depth[2];
  EXPECT_EQ(near.from_m, 0.0);
  EXPECT_EQ(near.to_m, 10.0);
  EXPECT_EQ(far.from_m, 30.0);
  EXPECT_TRUE(std::isinf(far.to_m));
  // Covered (x < 5, 200 samples): depth 2y < 10 m for y < 5 (100), else 10-20 m. Uncovered (200): 25 + y, in
  // [25, 30) for y < 5 (100), else >= 30 m.
  EXPECT_EQ(near.samples, 100);
  EXPECT_EQ(mid.samples, 200);
  EXPECT_EQ(far.samples, 100);
  EXPECT_DOUBLE_EQ(near.completeness, 1.0);
  EXPECT_DOUBLE_EQ(mid.completeness, 0.5);
  EXPECT_DOUBLE_EQ(far.completeness, 0.0);
  EXPECT_DOUBLE_EQ(s.completeness, 0.5);  // the same as without depths
  EXPECT_TRUE(CompareSurfaces(Square(0, 5, 0.1), truth, samples, options).completeness_by_depth.empty());
  // Without a reconstruction the bands still count their samples, none of them covered.
  const SurfaceMetrics empty = CompareSurfaces(Mesh(), truth, samples, options, depths);
  EXPECT_EQ(empty.completeness_by_depth[1].samples, 200);
  EXPECT_EQ(empty.completeness_by_depth[1].completeness, 0.0);
  SurfaceMetricsOptions bad;
  bad.completeness_depth_edges_m = {10.0, 5.0};
  EXPECT_THROW(CompareSurfaces(Square(0, 5, 0.1), truth, samples, bad, depths), InvalidOption);
}

TEST(SurfaceMetrics, EmptyReconstructionIsIncompleteAndBadThresholdThrows) {
  const SurfaceMetrics empty = CompareSurfaces(Mesh(), Square(0, 10, 0), TruthSamples());
  EXPECT_EQ(empty.completeness, 0.0);
  EXPECT_EQ(empty.accuracy, 0.0);
  EXPECT_EQ(empty.area_m2, 0.0);
  EXPECT_EQ(empty.area_samples, 0);
  EXPECT_EQ(empty.vertex_samples, 0);
  SurfaceMetricsOptions bad;
  bad.threshold_m = 0.0;
  EXPECT_THROW(CompareSurfaces(Square(0, 1, 0), Square(0, 10, 0), TruthSamples(), bad), InvalidOption);
}

}  // namespace
}  // namespace semap
