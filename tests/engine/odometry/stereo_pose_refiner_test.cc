#include "engine/odometry/internal/stereo_pose_refiner.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "tests/engine/odometry/kitti_calibration.h"

namespace semap::odometry_internal {
namespace {

Pose3d Motion() {
  Pose3d m = Pose3d::Identity();
  m.linear() =
      (Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.005, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  m.translation() = Eigen::Vector3d(0.05, -0.02, -1.2);  // cur_from_ref: the camera drove ~1.2 m forward
  return m;
}

// Matches of random points in front of both cameras, observed with Gaussian pixel noise `noise_px`.
std::vector<StereoMatch> Matches(const StereoCalibration& c, const Pose3d& cur_from_ref, int n,
                                 double noise_px, std::mt19937* rng) {
  std::uniform_real_distribution<double> x(-15.0, 15.0), y(-3.0, 2.0), z(4.0, 40.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<StereoMatch> out;
  while (static_cast<int>(out.size()) < n) {
    const Eigen::Vector3d p_ref(x(*rng), y(*rng), z(*rng));
    const Eigen::Vector3d p_cur = cur_from_ref * p_ref;
    if (p_cur.z() < 2.0) continue;
    StereoMatch m;
    m.ref_left_px = c.Project(p_ref) + Eigen::Vector2d(noise(*rng), noise(*rng));
    m.ref_right_u_px = c.Project(p_ref - Eigen::Vector3d(c.baseline_m, 0, 0)).x() + noise(*rng);
    m.cur_left_px = c.Project(p_cur) + Eigen::Vector2d(noise(*rng), noise(*rng));
    m.cur_right_u_px = c.Project(p_cur - Eigen::Vector3d(c.baseline_m, 0, 0)).x() + noise(*rng);
    m.has_current_right = true;
    out.push_back(m);
  }
  return out;
}

TEST(StereoPoseRefiner, ExactMatchesGiveTheExactMotionFromARoughStart) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(1);
  const std::vector<StereoMatch> matches = Matches(c, Motion(), 200, 0.0, &rng);
  Pose3d start = Motion();
  start.translation() += Eigen::Vector3d(0.1, 0.05, 0.2);
  start.linear() = start.linear() * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const RefinedMotion r = RefineStereoMotion(c, matches, start, std::vector<bool>(matches.size(), true), {});
  EXPECT_LT((r.cur_from_ref.translation() - Motion().translation()).norm(), 1e-6);
  EXPECT_LT((r.cur_from_ref.linear() - Motion().linear()).norm(), 1e-8);
  EXPECT_EQ(r.num_inliers, 200);
  EXPECT_LT(r.rms_px, 1e-4);
}

TEST(StereoPoseRefiner, OutliersAreFoundAndDoNotPullTheMotion) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(2);
  constexpr double kNoisePx = 0.3;
  std::vector<StereoMatch> matches = Matches(c, Motion(), 300, kNoisePx, &rng);
  // Every fifth match is wrong by 20 px in the current image (a mistracked feature).
  for (size_t i = 0; i < matches.size(); i += 5) matches[i].cur_left_px.x() += 20.0;
  const RefinedMotion r =
      RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), {});
  for (size_t i = 0; i < matches.size(); i += 5) EXPECT_FALSE(r.inliers[i]) << i;
  EXPECT_GT(r.num_inliers, 200);
  // 240 good matches at 0.3 px: a few centimetres and a few hundredths of a degree.
  EXPECT_LT((r.cur_from_ref.translation() - Motion().translation()).norm(), 0.03);
  EXPECT_LT(Eigen::AngleAxisd(r.cur_from_ref.linear() * Motion().linear().transpose()).angle(), 5e-4);
  EXPECT_LT(r.rms_px, 2 * kNoisePx);
}

// The right image of a rig whose rectification is off: every right u lands `offset_px` to the right, so every
// measured disparity is that much short of the true one.
std::vector<StereoMatch> WithRightOffset(std::vector<StereoMatch> matches, double offset_px) {
  for (auto& m : matches) {
    m.ref_right_u_px += offset_px;
    m.cur_right_u_px += offset_px;
  }
  return matches;
}

TEST(StereoPoseRefiner, ExactMatchesGiveTheDisparityOffsetAndTheMotion) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(3);
  constexpr double kOffsetPx = 0.4;
  const std::vector<StereoMatch> matches = WithRightOffset(Matches(c, Motion(), 200, 0.0, &rng), kOffsetPx);
  RefinerOptions o;
  o.estimate_offset_terms = 1;
  const RefinedMotion r =
      RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), o);
  EXPECT_NEAR(r.disparity_offset.constant_px, kOffsetPx, 1e-6);
  EXPECT_EQ(r.disparity_offset.per_row_px, 0.0);
  EXPECT_LT((r.cur_from_ref.translation() - Motion().translation()).norm(), 1e-6);
  EXPECT_LT((r.cur_from_ref.linear() - Motion().linear()).norm(), 1e-8);
  EXPECT_EQ(r.num_inliers, 200);
  // Given the offset instead, the same.
  o.estimate_offset_terms = 0;
  o.disparity_offset.constant_px = kOffsetPx;
  const RefinedMotion given =
      RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), o);
  EXPECT_LT((given.cur_from_ref.translation() - Motion().translation()).norm(), 1e-6);
  EXPECT_EQ(given.disparity_offset.constant_px, kOffsetPx);
  EXPECT_EQ(given.disparity_offset_sigma_px, 0.0);
}

// A rig whose offset grows with the row (a roll between the cameras): exact matches give both terms.
TEST(StereoPoseRefiner, ExactMatchesGiveBothTermsOfAPerRowOffset) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(8);
  const DisparityOffset truth{0.3, 1.5};
  std::vector<StereoMatch> matches = Matches(c, Motion(), 300, 0.0, &rng);
  for (auto& m : matches) {
    m.ref_right_u_px += truth.At(m.ref_left_px.y(), c);
    m.cur_right_u_px += truth.At(m.cur_left_px.y(), c);
  }
  RefinerOptions o;
  o.estimate_offset_terms = 2;
  const RefinedMotion r =
      RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), o);
  EXPECT_NEAR(r.disparity_offset.constant_px, truth.constant_px, 1e-6);
  EXPECT_NEAR(r.disparity_offset.per_row_px, truth.per_row_px, 1e-5);
  EXPECT_LT((r.cur_from_ref.translation() - Motion().translation()).norm(), 1e-6);
  EXPECT_EQ(r.num_inliers, 300);
}

// With pixel noise, the estimate lands within a few of its own standard deviations of the truth, the
// standard deviation is what the noise implies, and ignoring the offset stretches the step.
TEST(StereoPoseRefiner, NoisyMatchesGiveTheOffsetWithinItsStandardDeviation) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  constexpr double kNoisePx = 0.3;
  constexpr double kOffsetPx = 0.5;
  constexpr double kSigmas = 4.0;
  for (const unsigned seed : {4u, 5u, 6u}) {
    std::mt19937 rng(seed);
    const std::vector<StereoMatch> matches =
        WithRightOffset(Matches(c, Motion(), 300, kNoisePx, &rng), kOffsetPx);
    RefinerOptions o;
    o.estimate_offset_terms = 1;
    const RefinedMotion r =
        RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), o);
    EXPECT_GT(r.disparity_offset_sigma_px, 0.0);
    EXPECT_LT(r.disparity_offset_sigma_px,
              kNoisePx);  // 300 matches tell it far better than one pixel's noise
    EXPECT_NEAR(r.disparity_offset.constant_px, kOffsetPx, kSigmas * r.disparity_offset_sigma_px)
        << "seed " << seed;
    const RefinedMotion ignored =
        RefineStereoMotion(c, matches, Motion(), std::vector<bool>(matches.size(), true), RefinerOptions{});
    const double step_m = Motion().translation().norm();
    EXPECT_LT(std::abs(r.cur_from_ref.translation().norm() - step_m),
              std::abs(ignored.cur_from_ref.translation().norm() - step_m))
        << "seed " << seed;
  }
}

// Without motion the depths cannot tell the offset: its standard deviation says so.
TEST(StereoPoseRefiner, StandingStillCannotTellTheOffset) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(7);
  const std::vector<StereoMatch> matches = Matches(c, Pose3d::Identity(), 300, 0.3, &rng);
  RefinerOptions o;
  o.estimate_offset_terms = 1;
  const RefinedMotion r =
      RefineStereoMotion(c, matches, Pose3d::Identity(), std::vector<bool>(matches.size(), true), o);
  const std::vector<StereoMatch> moving = Matches(c, Motion(), 300, 0.3, &rng);
  const RefinedMotion m = RefineStereoMotion(c, moving, Motion(), std::vector<bool>(moving.size(), true), o);
  EXPECT_GT(r.disparity_offset_sigma_px, 10.0 * m.disparity_offset_sigma_px);
}

TEST(StereoPoseRefiner, WithoutMatchesTheStartIsKept) {
  const RefinedMotion r = RefineStereoMotion(test::KittiOdometryCalibration(), {}, Motion(), {}, {});
  EXPECT_TRUE(r.cur_from_ref.isApprox(Motion()));
  EXPECT_EQ(r.num_inliers, 0);
}

}  // namespace
}  // namespace semap::odometry_internal
