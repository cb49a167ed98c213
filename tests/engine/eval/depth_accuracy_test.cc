#include "engine/eval/depth_accuracy.h"

#include <gtest/gtest.h>

#include "engine/core/check.h"

namespace semap {
namespace {

TEST(DepthAccuracy, HandComputedErrorsAndCompleteness) {
  // Reference: 4 pixels in range, one too near, one too far; mesh: errors +1, -1, +3 and a hole.
  cv::Mat ref = (cv::Mat_<float>(2, 3) << 10, 10, 10, 10, 0.5f, 50);
  cv::Mat mesh = (cv::Mat_<float>(2, 3) << 11, 9, 13, 0, 7, 7);
  DepthAccuracyAccumulator acc;
  acc.Add(ref, mesh);
  const auto a = acc.Result();
  EXPECT_EQ(a.reference_pixels, 4);
  EXPECT_EQ(a.compared_pixels, 3);
  EXPECT_DOUBLE_EQ(a.completeness, 0.75);
  EXPECT_NEAR(a.rmse_m, std::sqrt((1.0 + 1.0 + 9.0) / 3.0), 1e-9);
  EXPECT_NEAR(a.mae_m, 5.0 / 3.0, 1e-9);
  EXPECT_NEAR(a.mean_error_m, 1.0, 1e-9);
  EXPECT_NEAR(a.median_abs_m, 1.0, 1e-9);
}

TEST(DepthAccuracy, OutlierFilterOnlyWhenAsked) {
  cv::Mat ref = (cv::Mat_<float>(1, 2) << 10, 10);
  cv::Mat mesh = (cv::Mat_<float>(1, 2) << 10.5f, 15);
  DepthAccuracyOptions o;
  o.max_abs_error_m = 2.0;
  DepthAccuracyAccumulator filtered(o), all;
  filtered.Add(ref, mesh);
  all.Add(ref, mesh);
  EXPECT_NEAR(filtered.Result().rmse_m, 0.5, 1e-6);
  EXPECT_DOUBLE_EQ(filtered.Result().completeness, 1.0);  // an outlier is still covered
  EXPECT_NEAR(all.Result().rmse_m, std::sqrt((0.25 + 25.0) / 2.0), 1e-6);
}

TEST(DepthAccuracy, MergeEqualsAddingEverything) {
  cv::Mat ref = (cv::Mat_<float>(1, 3) << 5, 6, 7);
  cv::Mat mesh = (cv::Mat_<float>(1, 3) << 5.5f, 0, 6);
  DepthAccuracyAccumulator a, b, both;
  a.Add(ref, mesh);
  b.Add(ref, ref);
  both.Add(ref, mesh);
  both.Add(ref, ref);
  a.Merge(b);
  EXPECT_DOUBLE_EQ(a.Result().rmse_m, both.Result().rmse_m);
  EXPECT_EQ(a.Result().reference_pixels, 6);
  EXPECT_DOUBLE_EQ(a.Result().completeness, 5.0 / 6.0);
}

TEST(LidarDepthImage, ProjectsNearestPointInFrontUsingCameraZ) {
  StereoCalibration cal;
  cal.fx_px = cal.fy_px = 100;
  cal.cx_px = 50;
  cal.cy_px = 40;
  cal.baseline_m = 0.5;
  cal.width_px = 100;
  cal.height_px = 80;
  VelodyneScan scan;
  // Velodyne x forward, y left, z up → camera x right, y down, z forward.
  Eigen::Matrix3d r;
  r << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  scan.cam_from_velo.linear() = r;
  scan.points_velo = {{10, 0, 0, 1}, {12, 0, 0, 1}, {-10, 0, 0, 1}, {10, -1, 0, 1}, {100, 0, 0, 1}};
  const cv::Mat d = LidarDepthImage(scan, cal, DepthAccuracyOptions{});
  EXPECT_FLOAT_EQ(d.at<float>(40, 50), 10.0f);  // nearest of the two on the optical axis
  EXPECT_FLOAT_EQ(d.at<float>(40, 60),
                  10.0f);             // 1 m right at 10 m: u = 50 + 100·1/10 = 60, z (not range) = 10
  EXPECT_EQ(cv::countNonZero(d), 2);  // behind the camera and beyond 40 m are dropped
}

TEST(DepthAccuracyOptions, CheckNamesTheField) {
  DepthAccuracyOptions o;
  o.max_depth_m = 0.5;
  try {
    o.Check();
    FAIL();
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "max_depth_m");
  }
}

TEST(DepthAccuracy, PaperProtocolIsTheStrictOneCutAt15mAndTwoMetreErrors) {
  DepthAccuracyOptions strict;
  const DepthAccuracyOptions paper = PaperProtocol(strict);
  EXPECT_DOUBLE_EQ(paper.min_depth_m, strict.min_depth_m);
  EXPECT_DOUBLE_EQ(paper.max_depth_m, 15.0);
  EXPECT_DOUBLE_EQ(paper.max_abs_error_m, 2.0);
  strict.max_depth_m = 12.0;
  EXPECT_DOUBLE_EQ(PaperProtocol(strict).max_depth_m, 12.0);  // never beyond the strict range
  EXPECT_EQ(ProtocolFilters(DepthAccuracyOptions()), "reference depth 1-40 m, every error");
  EXPECT_EQ(ProtocolFilters(paper), "reference depth 1-15 m, |error| <= 2 m");
  // Errors +0.5, +5 (excluded by the paper only) and a 20 m reference (strict only).
  cv::Mat ref = (cv::Mat_<float>(1, 3) << 10, 10, 20);
  cv::Mat mesh = (cv::Mat_<float>(1, 3) << 10.5f, 15, 20);
  DepthAccuracyAccumulator s, p(paper);
  s.Add(ref, mesh);
  p.Add(ref, mesh);
  EXPECT_EQ(s.Result().compared_pixels, 3);
  EXPECT_EQ(s.Result().excluded_pixels, 0);
  EXPECT_EQ(p.Result().reference_pixels, 2);
  EXPECT_EQ(p.Result().compared_pixels, 2);
  EXPECT_EQ(p.Result().excluded_pixels, 1);
  EXPECT_NEAR(p.Result().rmse_m, 0.5, 1e-6);
  EXPECT_NEAR(s.Result().rmse_m, std::sqrt((0.25 + 25.0) / 3.0), 1e-6);
}

}  // namespace
}  // namespace semap
