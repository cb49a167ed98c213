#include "engine/eval/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace semap {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A drive along z at `step_m` per frame, turning about y by `turn_rad` per frame.
std::vector<Pose3d> Drive(int frames, double step_m, double turn_rad) {
  std::vector<Pose3d> out;
  Pose3d p = Pose3d::Identity();
  Pose3d step = Pose3d::Identity();
  step.linear() = Eigen::AngleAxisd(turn_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  step.translation() = Eigen::Vector3d(0, 0, step_m);
  for (int i = 0; i < frames; ++i) {
    out.push_back(p);
    p = p * step;
  }
  return out;
}

TEST(TrajectoryMetrics, APerfectEstimateHasNoError) {
  const auto truth = Drive(1000, 1.0, 0.002);
  const auto k = KittiOdometryMetric(truth, truth);
  ASSERT_GT(k.overall.segments, 0);
  EXPECT_NEAR(k.overall.translation_percent, 0.0, 1e-9);
  EXPECT_NEAR(k.overall.rotation_deg_per_m, 0.0, 1e-6);
  EXPECT_EQ(k.per_length.size(), 8u);  // 100..800 m all fit in 999 m
  const auto r = RelativeError(truth, truth, 10);
  EXPECT_EQ(r.windows, 990);
  EXPECT_NEAR(r.drift.translation_percent, 0.0, 1e-9);
  const auto a = AbsoluteError(truth, truth);
  EXPECT_NEAR(a.rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(a.path_length_m, 999.0, 1e-6);
}

// An estimate 1 % too long: 1 % translation error on every segment, no rotation error.
TEST(TrajectoryMetrics, AScaleErrorIsItsPercentage) {
  const auto truth = Drive(900, 1.0, 0.0);
  const auto estimate = Drive(900, 1.01, 0.0);
  const auto k = KittiOdometryMetric(truth, estimate);
  EXPECT_NEAR(k.overall.translation_percent, 1.0, 1e-6);
  EXPECT_NEAR(k.overall.rotation_deg_per_m, 0.0, 1e-9);
  EXPECT_EQ(k.per_length.front().segments, 80);  // starts every 10 frames with 100 m ahead: 0..790
  const auto r = RelativeError(truth, estimate, 10);
  EXPECT_NEAR(r.drift.translation_percent, 1.0, 1e-6);
  EXPECT_NEAR(r.drift.length_m, 10.0, 1e-9);
  EXPECT_NEAR(r.translation_rmse_m, 0.1, 1e-9);
  const auto a = AbsoluteError(truth, estimate);
  EXPECT_NEAR(a.end_point_m, 8.99, 1e-6);
  EXPECT_NEAR(a.end_point_percent, 1.0, 1e-6);
}

// A heading drift of d rad per frame on a straight drive of 1 m frames: d rad per metre of rotation error.
TEST(TrajectoryMetrics, RotationDriftPerMetre) {
  const double drift_rad = 1e-4;
  const auto truth = Drive(300, 1.0, 0.0);
  const auto estimate = Drive(300, 1.0, drift_rad);
  const auto r = RelativeError(truth, estimate, 10);
  EXPECT_NEAR(r.drift.rotation_deg_per_m, drift_rad * 180.0 / kPi, 1e-9);
  const auto k = KittiOdometryMetric(truth, estimate);
  EXPECT_NEAR(k.overall.rotation_deg_per_m, drift_rad * 180.0 / kPi, 1e-9);
}

// The ATE does not see where the estimate's world frame is; the end-point error (from the common first pose)
// does not either.
TEST(TrajectoryMetrics, AbsoluteErrorIgnoresARigidOffsetOfTheEstimate) {
  const auto truth = Drive(200, 1.0, 0.01);
  Pose3d offset = Pose3d::Identity();
  offset.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  offset.translation() = Eigen::Vector3d(5, -3, 10);
  std::vector<Pose3d> moved;
  for (const auto& p : truth) moved.push_back(offset * p);
  const auto a = AbsoluteError(truth, moved);
  EXPECT_NEAR(a.rmse_m, 0.0, 1e-6);
  EXPECT_NEAR(a.end_point_m, 0.0, 1e-6);
  EXPECT_NEAR(a.end_rotation_deg, 0.0, 1e-4);
}

// Short drives: no KITTI segment; windows where the truth stands still are left out of the per-metre figures.
TEST(TrajectoryMetrics, ShortOrStandingDrives) {
  const auto still = Drive(30, 0.0, 0.0);
  EXPECT_EQ(KittiOdometryMetric(still, still).overall.segments, 0);
  const auto r = RelativeError(still, still, 10);
  EXPECT_EQ(r.windows, 20);
  EXPECT_EQ(r.drift.segments, 0);
  EXPECT_EQ(AbsoluteError({}, {}).rmse_m, 0.0);
}

// A drive whose heading and slope change along it (a turn that tightens and eases, a climb that comes and
// goes), so that its windows' directions span the camera frame's x–z plane and more.
std::vector<Pose3d> WindingDrive(int frames) {
  std::vector<Pose3d> out;
  Pose3d p = Pose3d::Identity();
  for (int i = 0; i < frames; ++i) {
    out.push_back(p);
    Pose3d step = Pose3d::Identity();
    step.linear() = (Eigen::AngleAxisd(0.03 * std::sin(0.05 * i), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(0.01 * std::cos(0.07 * i), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    step.translation() = Eigen::Vector3d(0, 0, 1.0);
    p = p * step;
  }
  return out;
}

// An estimate that is the truth seen from a camera frame rotated by a known R: the fit finds R, and with R
// taken out the relative error all but vanishes. Not exactly: the weak pull towards the identity (0.01 of a
// window per axis) holds back the axis this drive tells least, the pitch, by a few thousandths of a degree.
TEST(TrajectoryMetrics, AFixedFrameRotationIsFoundAndTakenOut) {
  const auto truth = WindingDrive(300);
  Pose3d extrinsic = Pose3d::Identity();
  const Eigen::Vector3d angles_rad(0.4 * kPi / 180, 0.5 * kPi / 180, -0.2 * kPi / 180);
  extrinsic.linear() = Eigen::AngleAxisd(angles_rad.norm(), angles_rad.normalized()).toRotationMatrix();
  std::vector<Pose3d> estimate;
  for (const Pose3d& p : truth) estimate.push_back(p * extrinsic);
  // With the rotation in it, every motion of the estimate is off: its direction by the rotation's ~0.7°.
  const RelativePoseError before = RelativeError(truth, estimate, 10);
  EXPECT_GT(before.drift.translation_percent, 0.5);
  const FrameRotationFit fit = FitFrameRotation(truth, estimate, 10);
  constexpr double kPullBiasDeg = 0.01;
  EXPECT_NEAR(fit.angles_deg.x(), 0.4, kPullBiasDeg);
  EXPECT_NEAR(fit.angles_deg.y(), 0.5, kPullBiasDeg);
  EXPECT_NEAR(fit.angles_deg.z(), -0.2, kPullBiasDeg);
  EXPECT_LT(fit.relative.drift.translation_percent, 0.05 * before.drift.translation_percent);
  EXPECT_LT(fit.relative.drift.rotation_deg_per_m, 0.05 * before.drift.rotation_deg_per_m);
}

// A straight drive cannot tell a roll about its direction: the fit adds none, and an estimate that is right
// gets the identity.
TEST(TrajectoryMetrics, AStraightDriveGetsNoFrameRotation) {
  const auto truth = Drive(100, 1.0, 0.0);
  const FrameRotationFit fit = FitFrameRotation(truth, truth, 10);
  EXPECT_TRUE(fit.truth_cam_from_estimate_cam.isApprox(Eigen::Matrix3d::Identity(), 1e-9));
  EXPECT_LT(fit.relative.drift.translation_percent, 1e-9);
}

}  // namespace
}  // namespace semap
