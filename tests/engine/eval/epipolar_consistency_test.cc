#include "engine/eval/epipolar_consistency.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace semap {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

StereoCalibration Kitti() {
  StereoCalibration k;
  k.fx_px = k.fy_px = 718.856;
  k.cx_px = 607.1928;
  k.cy_px = 185.2157;
  k.baseline_m = 0.537;
  k.width_px = 1241;
  k.height_px = 376;
  return k;
}

Eigen::Matrix3d RotationDeg(double x, double y, double z) {
  const Eigen::Vector3d v(x, y, z);
  return Eigen::AngleAxisd(v.norm() * kDegToRad, v.normalized()).toRotationMatrix();
}

// Windows of exact tracks of a camera driving forward and turning, as the images of a camera frame rotated by
// `truth_from_image` from the poses' frame see them; the windows carry the poses' motions.
std::vector<TrackWindow> ExactWindows(const Eigen::Matrix3d& truth_from_image) {
  const StereoCalibration k = Kitti();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-15.0, 15.0), y(-3.0, 2.0), z(6.0, 40.0);
  std::vector<TrackWindow> windows;
  for (int w = 0; w < 6; ++w) {
    TrackWindow window;
    window.b_from_a.linear() = RotationDeg(0.2, 4.0 * (w - 2), 0.1).transpose();
    window.b_from_a.translation() = -window.b_from_a.linear() * Eigen::Vector3d(0.3 * w - 0.6, 0.05, 8.0);
    const Eigen::Matrix3d r = truth_from_image.transpose() * window.b_from_a.linear() * truth_from_image;
    const Eigen::Vector3d t = truth_from_image.transpose() * window.b_from_a.translation();
    while (window.a_px.size() < 300) {
      const Eigen::Vector3d pa(x(rng), y(rng), z(rng));
      const Eigen::Vector3d pb = r * pa + t;
      if (pb.z() <= 1.0) continue;
      const Eigen::Vector2d ua = k.Project(pa), ub = k.Project(pb);
      if (!k.InImage(ua) || !k.InImage(ub)) continue;
      window.a_px.push_back(ua);
      window.b_px.push_back(ub);
    }
    windows.push_back(std::move(window));
  }
  return windows;
}

TEST(EpipolarConsistency, AVerticalOffsetUnderASidewaysMotionIsItsSampsonDistance) {
  // The camera moves along x: the epipolar lines are the image rows, and a match one row apart is off by
  // 1/√2 px in Sampson's first-order distance (the correction shared between the two images).
  Pose3d b_from_a = Pose3d::Identity();
  b_from_a.translation() = Eigen::Vector3d(-0.5, 0.0, 0.0);
  const StereoCalibration k = Kitti();
  EXPECT_NEAR(SampsonDistancePx(k, b_from_a, {400.0, 200.0}, {380.0, 200.0}), 0.0, 1e-12);
  EXPECT_NEAR(SampsonDistancePx(k, b_from_a, {400.0, 200.0}, {380.0, 201.0}), 1.0 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(SampsonDistancePx(k, b_from_a, {900.0, 50.0}, {700.0, 47.0}), 3.0 / std::sqrt(2.0), 1e-9);
  // No translation, no epipolar geometry.
  EXPECT_EQ(SampsonDistancePx(k, Pose3d::Identity(), {400.0, 200.0}, {380.0, 201.0}), 0.0);
}

TEST(EpipolarConsistency, ExactTracksAgreeWithTheirOwnPoses) {
  const std::vector<TrackWindow> windows = ExactWindows(Eigen::Matrix3d::Identity());
  const EpipolarAgreement a = EpipolarAgreementOf(windows, Kitti(), Eigen::Matrix3d::Identity(), 2.0);
  EXPECT_EQ(a.tracks, 1800);
  EXPECT_LT(a.mean_px, 1e-9);
  EXPECT_LT(a.median_px, 1e-9);
}

TEST(EpipolarConsistency, AFixedFrameRotationIsFoundAndTakenOut) {
  const Eigen::Matrix3d r0 = RotationDeg(0.3, 0.8, -0.1);
  const std::vector<TrackWindow> windows = ExactWindows(r0);
  const EpipolarAgreement as_given = EpipolarAgreementOf(windows, Kitti(), Eigen::Matrix3d::Identity(), 2.0);
  EXPECT_GT(as_given.median_px, 0.5);  // 0.8° is ~10 px of the focus of expansion
  EXPECT_LT(EpipolarAgreementOf(windows, Kitti(), r0, 2.0).mean_px, 1e-9);
  const EpipolarRotationFit fit = FitEpipolarRotation(windows, Kitti(), 2.0);
  EXPECT_NEAR(fit.angles_deg.x(), 0.3, 0.02);
  EXPECT_NEAR(fit.angles_deg.y(), 0.8, 0.02);
  EXPECT_NEAR(fit.angles_deg.z(), -0.1, 0.02);
  EXPECT_LT(fit.agreement.mean_px, 0.05 * as_given.mean_px);
}

TEST(EpipolarConsistency, TheCapBoundsWhatOneMistrackAdds) {
  std::vector<TrackWindow> windows = ExactWindows(Eigen::Matrix3d::Identity());
  windows[0].b_px[0].y() += 50.0;  // a mistrack far off its line
  const EpipolarAgreement a = EpipolarAgreementOf(windows, Kitti(), Eigen::Matrix3d::Identity(), 2.0);
  EXPECT_NEAR(a.mean_px, 2.0 / 1800.0, 1e-9);
  EXPECT_LT(a.median_px, 1e-9);
}

}  // namespace
}  // namespace semap
