#include "bench/fountain_geometry.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace semap::bench {
namespace {

// A camera at `centre_world` looking at `target_world`, y down, with fountain-P11-like intrinsics.
PinholeCamera LookAt(const Eigen::Vector3d& centre_world, const Eigen::Vector3d& target_world) {
  const Eigen::Vector3d z = (target_world - centre_world).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  PinholeCamera c;
  c.K << 1380.0, 0.0, 760.0, 0.0, 1382.0, 503.0, 0.0, 0.0, 1.0;
  c.world_from_cam.linear().col(0) = x;
  c.world_from_cam.linear().col(1) = y;
  c.world_from_cam.linear().col(2) = z;
  c.world_from_cam.translation() = centre_world;
  return c;
}

std::vector<PinholeCamera> ThreeCameras() {
  const Eigen::Vector3d target(0.0, 0.0, 10.0);
  return {LookAt({-1.0, 0.0, 0.0}, target), LookAt({0.0, 0.2, 0.0}, target),
          LookAt({1.2, -0.1, 0.3}, target)};
}

TEST(FountainGeometry, TriangulatesAPointSeenByThreeCameras) {
  const Eigen::Vector3d p_world(0.7, -0.4, 9.3);
  std::vector<Observation> observations;
  for (const PinholeCamera& c : ThreeCameras()) observations.push_back({c, ProjectPx(c, p_world)});
  const auto linear = TriangulateLinear(observations);
  ASSERT_TRUE(linear.has_value());
  EXPECT_LT((*linear - p_world).norm(), 1e-6);
  const auto kept = TriangulateTrack(observations, 0.5);
  ASSERT_TRUE(kept.has_value());
  EXPECT_LT((*kept - p_world).norm(), 1e-6);
  for (double e : ReprojectionErrorsPx(observations, *kept)) EXPECT_LT(e, 1e-6);
}

TEST(FountainGeometry, ReprojectionErrorsOfNoisyObservations) {
  const Eigen::Vector3d p_world(-0.5, 0.3, 10.5);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise_px(0.0, 0.2);
  std::vector<Observation> observations;
  for (const PinholeCamera& c : ThreeCameras()) {
    observations.push_back({c, ProjectPx(c, p_world) + Eigen::Vector2d(noise_px(rng), noise_px(rng))});
  }
  // At the true point the errors are the noise added.
  const std::vector<double> at_truth = ReprojectionErrorsPx(observations, p_world);
  ASSERT_EQ(at_truth.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(at_truth[i], (observations[i].uv_px - ProjectPx(observations[i].camera, p_world)).norm(),
                1e-9);
  }
  // The refined point fits the observations no worse than the truth does, and lies near it.
  const Eigen::Vector3d refined = RefineReprojection(observations, *TriangulateLinear(observations), 5);
  double sq_truth = 0.0, sq_refined = 0.0;
  const std::vector<double> at_refined = ReprojectionErrorsPx(observations, refined);
  for (size_t i = 0; i < 3; ++i) {
    sq_truth += at_truth[i] * at_truth[i];
    sq_refined += at_refined[i] * at_refined[i];
  }
  EXPECT_LE(sq_refined, sq_truth + 1e-12);
  EXPECT_LT((refined - p_world).norm(), 0.05);
  // An observation 3 px off fails a 0.5 px bound; a point behind a camera has an infinite error.
  observations[1].uv_px.x() += 3.0;
  EXPECT_FALSE(TriangulateTrack(observations, 0.5).has_value());
  const std::vector<double> behind = ReprojectionErrorsPx(observations, Eigen::Vector3d(0.0, 0.0, -5.0));
  EXPECT_TRUE(std::isinf(behind[0]));
}

TEST(FountainGeometry, RejectsATrackWithTwoKeypointsInOneView) {
  const std::vector<KeypointMatch> matches = {
      {{0, 1}, {1, 4}}, {{1, 4}, {2, 9}},                    // 0:1 – 1:4 – 2:9, three views
      {{0, 2}, {1, 5}}, {{1, 5}, {2, 7}}, {{2, 7}, {0, 3}},  // 0:2 and 0:3 in one track
      {{3, 0}, {4, 0}},                                      // two views only
  };
  const auto tracks = BuildTracks(matches, 3);
  ASSERT_EQ(tracks.size(), 1u);
  const std::vector<ViewKeypoint> expected = {{0, 1}, {1, 4}, {2, 9}};
  EXPECT_EQ(tracks[0], expected);
  EXPECT_EQ(BuildTracks(matches, 2).size(), 2u);
}

TEST(FountainGeometry, MatchesOnTheEpipolarLine) {
  const std::vector<PinholeCamera> cameras = ThreeCameras();
  const Eigen::Vector3d p_world(0.3, 0.2, 11.0);
  const Eigen::Matrix3d F = FundamentalMatrix(cameras[0], cameras[2]);
  const Eigen::Vector2d xa = ProjectPx(cameras[0], p_world), xb = ProjectPx(cameras[2], p_world);
  EXPECT_LT(EpipolarDistancePx(F, xa, xb), 1e-6);
  EXPECT_GT(EpipolarDistancePx(F, xa, xb + Eigen::Vector2d(0.0, 5.0)), 1.0);
}

}  // namespace
}  // namespace semap::bench
