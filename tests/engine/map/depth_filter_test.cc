// A vertex's depth filter (engine/map/internal/depth_filter.h) against simple references: the error of the
// fused estimate falls as 1/√n with its sightings; the streamed estimate is the batch inverse-variance mean
// of the same sightings; a vertex the views see through is an outlier, one they see in front of is not.
#include "engine/map/internal/depth_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

constexpr int kWidthPx = 40;
constexpr int kHeightPx = 30;
constexpr double kFocalPx = 30.0;
constexpr double kWallM = 10.0;
constexpr double kDisparitySigmaPx = 0.05;  // σ_z = 0.33 m at the wall

// A camera at (x_m, 0, 0) looking along +z, seeing a wall at z = depth_m over the whole image (constant
// depth: a fronto-parallel wall, plus whatever noise `depth_m` carries).
VotingView WallView(double x_m, float depth_m) {
  auto view = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  view->depth_m.setTo(depth_m);
  view->world_from_cam.translation() = Eigen::Vector3d(x_m, 0.0, 0.0);
  return VotingView(view);
}

// σ_z of a sighting of the wall by WallView (f·B = 30 px · 0.5 m).
double WallSigmaM() { return kWallM * kWallM * kDisparitySigmaPx / (kFocalPx * 0.5); }

// n sightings of a vertex on the wall straight ahead of the first camera, each view's depth off by its own
// draw of σ_z; the vertex follows its estimate (map.fuse_move_sigmas = 0). Returns the estimate's error in
// depth after each sighting (index 0: the first sighting alone).
std::vector<double> FusedErrors(int n, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, WallSigmaM());
  std::uniform_real_distribution<double> camera_x(-1.0, 1.0);
  const Eigen::Vector3d first(0.0, 0.0, kWallM + noise(*rng));
  DepthFilter filter;
  filter.Start(first, WallSigmaM());
  std::vector<double> errors{first.z() - kWallM};
  for (int k = 1; k < n; ++k) {
    const VotingView view = WallView(camera_x(*rng), float(kWallM + noise(*rng)));
    const Sighting s =
        ObserveVertex(filter.Estimate(), view, kDisparitySigmaPx, /*gate_sigmas=*/5.0, &filter);
    EXPECT_EQ(s, Sighting::kInlier);
    errors.push_back(filter.Estimate().z() - kWallM);
  }
  return errors;
}

TEST(DepthFilter, FusedErrorFallsAsOneOverRootN) {
  constexpr int kTrials = 400;
  constexpr int kSightings = 16;
  std::mt19937 rng(7);
  std::vector<double> sum_sq(kSightings, 0.0), sum(kSightings, 0.0);
  for (int t = 0; t < kTrials; ++t) {
    const std::vector<double> e = FusedErrors(kSightings, &rng);
    for (int k = 0; k < kSightings; ++k) {
      sum_sq[k] += e[k] * e[k];
      sum[k] += e[k];
    }
  }
  // The RMS error of n sightings against σ/√n: the sampling error of an RMS over 400 trials is ~3.5 %, and
  // the off-axis cameras see the wall slightly obliquely (σ along the ray within 1 % of σ_z).
  for (int n : {1, 2, 4, 8, 16}) {
    const double rms = std::sqrt(sum_sq[n - 1] / kTrials);
    const double expected = WallSigmaM() / std::sqrt(double(n));
    EXPECT_NEAR(rms / expected, 1.0, 0.12) << n << " sightings";
    // Centred: the mean error is within 4 standard errors of 0.
    EXPECT_LT(std::abs(sum[n - 1] / kTrials), 4.0 * expected / std::sqrt(double(kTrials)))
        << n << " sightings";
  }
}

TEST(DepthFilter, StreamedEstimateIsTheBatchInverseVarianceMean) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> depth(9.0, 11.0), sigma(0.05, 0.5);
  DepthFilter filter;
  Eigen::Vector3d batch_sum = Eigen::Vector3d::Zero();
  double batch_weight = 0.0;
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d x(0.1 * k, -0.05 * k, depth(rng));
    const double s = sigma(rng);
    if (k == 0) {
      filter.Start(x, s);
    } else {
      filter.AddInlier(x, s);
    }
    batch_sum += x / (s * s);
    batch_weight += 1.0 / (s * s);
  }
  EXPECT_LT((filter.Estimate() - batch_sum / batch_weight).norm(), 1e-12);
  EXPECT_NEAR(filter.Sigma(), 1.0 / std::sqrt(batch_weight), 1e-12);
}

TEST(DepthFilter, AVertexTheViewsSeeThroughIsAnOutlier) {
  // A vertex floating 2 m in front of the wall (an SGBM mismatch): each view sees the wall behind it.
  DepthFilter filter;
  const Eigen::Vector3d floating(0.0, 0.0, kWallM - 2.0);
  filter.Start(floating, 0.1);
  constexpr std::uint32_t kMinOutliers = 3;
  for (std::uint32_t k = 1; k <= kMinOutliers; ++k) {
    EXPECT_FALSE(filter.IsOutlier(kMinOutliers));
    EXPECT_EQ(ObserveVertex(floating, WallView(0.1 * k, kWallM), kDisparitySigmaPx, 3.0, &filter),
              Sighting::kOutlier);
  }
  EXPECT_EQ(filter.outliers, kMinOutliers);
  EXPECT_TRUE(filter.IsOutlier(kMinOutliers));
  EXPECT_FALSE(filter.IsOutlier(0)) << "0 = never";
  // Sky behind it is seen through too.
  EXPECT_EQ(ObserveVertex(floating, WallView(0.0, kFreeToFarRange), kDisparitySigmaPx, 3.0, &filter),
            Sighting::kOutlier);
}

TEST(DepthFilter, OcclusionAndMissingDepthAreNoEvidence) {
  DepthFilter filter;
  const Eigen::Vector3d on_wall(0.0, 0.0, kWallM);
  filter.Start(on_wall, WallSigmaM());
  // Something 5 m in front of the wall hides it; a view without depth there sees nothing; a vertex behind
  // the camera or outside the image is not in the view.
  EXPECT_EQ(ObserveVertex(on_wall, WallView(0.0, 5.0f), kDisparitySigmaPx, 3.0, &filter), Sighting::kNone);
  EXPECT_EQ(ObserveVertex(on_wall, WallView(0.0, 0.0f), kDisparitySigmaPx, 3.0, &filter), Sighting::kNone);
  EXPECT_EQ(
      ObserveVertex(Eigen::Vector3d(0, 0, -kWallM), WallView(0.0, kWallM), kDisparitySigmaPx, 3.0, &filter),
      Sighting::kNone);
  EXPECT_EQ(
      ObserveVertex(Eigen::Vector3d(50, 0, kWallM), WallView(0.0, kWallM), kDisparitySigmaPx, 3.0, &filter),
      Sighting::kNone);
  EXPECT_EQ(filter.inliers, 1u);
  EXPECT_EQ(filter.outliers, 0u);
  EXPECT_EQ(filter.Estimate(), on_wall);
  // A view that sees it counts.
  EXPECT_EQ(ObserveVertex(on_wall, WallView(0.5, kWallM), kDisparitySigmaPx, 3.0, &filter),
            Sighting::kInlier);
  EXPECT_EQ(filter.inliers, 2u);
}

TEST(DepthFilter, AtADepthEdgeASightingCountsWithoutMovingTheVertex) {
  // The left half of the image sees the wall, the right half a post 4 m nearer; the vertex on the wall
  // projects between the two halves.
  auto view = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  view->depth_m.setTo(float(kWallM));
  view->depth_m.colRange(kWidthPx / 2, kWidthPx).setTo(float(kWallM - 4.0));
  const VotingView edge(view);
  const Eigen::Vector3d on_wall((kWidthPx / 2 - 0.5 - view->intrinsics.cx_px) * kWallM / kFocalPx, 0.0,
                                kWallM);
  DepthFilter filter;
  filter.Start(on_wall, WallSigmaM());
  EXPECT_EQ(ObserveVertex(on_wall, edge, kDisparitySigmaPx, 3.0, &filter), Sighting::kInlier);
  EXPECT_EQ(filter.inliers, 2u);
  EXPECT_EQ(filter.Estimate(), on_wall) << "a depth edge gives no position";
}

}  // namespace
}  // namespace semap::map_internal
