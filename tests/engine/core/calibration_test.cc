#include "engine/core/calibration.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

StereoCalibration KittiLike() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 721.5377;
  c.cx_px = 609.5593;
  c.cy_px = 172.854;
  c.baseline_m = 0.5372;
  c.width_px = 1242;
  c.height_px = 375;
  return c;
}

TEST(StereoCalibration, ProjectUnprojectRoundTrip) {
  const auto c = KittiLike();
  const Eigen::Vector3d p(1.5, -0.7, 12.0);
  const Eigen::Vector2d uv = c.Project(p);
  EXPECT_NEAR(uv.x(), 721.5377 * 1.5 / 12.0 + 609.5593, 1e-9);
  const Eigen::Vector3d back = c.Unproject(uv.x(), uv.y(), p.z());
  EXPECT_NEAR((back - p).norm(), 0.0, 1e-12);
}

TEST(StereoCalibration, DepthDisparityAreInverse) {
  const auto c = KittiLike();
  // 721.5377 * 0.5372 / 38.76 ≈ 10 m
  EXPECT_NEAR(c.DepthFromDisparity(c.DisparityFromDepth(10.0)), 10.0, 1e-12);
  EXPECT_NEAR(c.DepthFromDisparity(38.76), 721.5377 * 0.5372 / 38.76, 1e-12);
}

TEST(StereoCalibration, Validity) {
  auto c = KittiLike();
  EXPECT_TRUE(c.IsValid());
  c.baseline_m = std::nan("");
  EXPECT_FALSE(c.IsValid());
  c = KittiLike();
  c.width_px = 0;
  EXPECT_FALSE(c.IsValid());
}

TEST(StereoCalibration, InImage) {
  const auto c = KittiLike();
  EXPECT_TRUE(c.InImage({0.0, 0.0}));
  EXPECT_TRUE(c.InImage({1241.9, 374.9}));
  EXPECT_FALSE(c.InImage({1242.0, 10.0}));
  EXPECT_FALSE(c.InImage({-0.1, 10.0}));
}

}  // namespace
}  // namespace semap
