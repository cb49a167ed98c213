#include "engine/eval/surface_metrics.h"

#include <gtest/gtest.h>

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
  EXPECT_NEAR(half.mean_accuracy_m, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(half.completeness, 0.5);
  EXPECT_EQ(half.reconstruction_samples, 4 + 2);
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
  EXPECT_DOUBLE_EQ(off.completeness, 0.0);
  SurfaceMetricsOptions loose;
  loose.threshold_m = 0.5;
  const SurfaceMetrics ok = CompareSurfaces(Square(0, 10, 0.3), truth, TruthSamples(), loose);
  EXPECT_DOUBLE_EQ(ok.accuracy, 1.0);
  EXPECT_DOUBLE_EQ(ok.completeness, 1.0);
}

TEST(SurfaceMetrics, EmptyReconstructionIsIncompleteAndBadThresholdThrows) {
  const SurfaceMetrics empty = CompareSurfaces(Mesh(), Square(0, 10, 0), TruthSamples());
  EXPECT_EQ(empty.completeness, 0.0);
  EXPECT_EQ(empty.reconstruction_samples, 0);
  SurfaceMetricsOptions bad;
  bad.threshold_m = 0.0;
  EXPECT_THROW(CompareSurfaces(Square(0, 1, 0), Square(0, 10, 0), TruthSamples(), bad), InvalidOption);
}

}  // namespace
}  // namespace semap
