#include "engine/depth/depth_metrics.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

TEST(EvaluateDisparity, CountsKittiD1WithMissingPixelsAsErrors) {
  cv::Mat gt = (cv::Mat_<float>(1, 6) << 10, 10, 100, 100, 50, 0);
  cv::Mat est = (cv::Mat_<float>(1, 6) << 12.9f, 13.5f, 104.9f, 105.5f, 0, 77);
  // px 0: err 2.9 (≤ 3) ok; px 1: 3.5 > 3 and > 0.5 → outlier; px 2: 4.9 > 3 but < 5 % of 100 → ok;
  // px 3: 5.5 > 3 and > 5 → outlier; px 4: no estimate → error; px 5: no ground truth → ignored.
  const DisparityMetrics m = EvaluateDisparity(est, gt);
  EXPECT_EQ(m.gt_pixels, 5u);
  EXPECT_EQ(m.estimated, 4u);
  EXPECT_EQ(m.outliers, 2u);
  EXPECT_DOUBLE_EQ(m.d1_all(), 3.0 / 5.0);
  EXPECT_DOUBLE_EQ(m.density(), 4.0 / 5.0);
  EXPECT_DOUBLE_EQ(m.d1_estimated(), 2.0 / 4.0);
  DisparityMetrics sum = m;
  sum += m;
  EXPECT_EQ(sum.gt_pixels, 10u);
  EXPECT_DOUBLE_EQ(sum.d1_all(), 3.0 / 5.0);
  EXPECT_THROW(EvaluateDisparity(est, cv::Mat(2, 2, CV_32F)), std::invalid_argument);
}

TEST(LidarDepthImage, KeepsTheNearestReturnPerPixelWithinRange) {
  StereoCalibration c;
  c.fx_px = c.fy_px = 100.0;
  c.cx_px = c.cy_px = 5.0;
  c.baseline_m = 0.5;
  c.width_px = c.height_px = 10;
  VelodyneScan scan;
  // Identity cam_from_velo: points given in the camera frame directly.
  scan.points_velo = {{0, 0, 10, 0}, {0, 0, 8, 0}, {0, 0, -5, 0}, {0, 0, 50, 0}, {100, 0, 10, 0}};
  const cv::Mat depth = LidarDepthImage(scan, c, 40.0);
  EXPECT_FLOAT_EQ(depth.at<float>(5, 5), 8.0f);
  EXPECT_EQ(cv::countNonZero(depth), 1);
}

TEST(DepthErrors, ComparesCameraFrameDepthAtThePointsPixel) {
  LabelledCloud cloud;
  cloud.positions_world = {{0, 0, 10.5}, {0, 0, 12}, {0, 0, 45}};
  cloud.pixels_px = {{1, 1}, {2, 2}, {1, 1}};
  cv::Mat lidar = cv::Mat::zeros(4, 4, CV_32F);
  lidar.at<float>(1, 1) = 10.0f;
  const auto e = DepthErrorsAgainstLidar(cloud, Pose3d::Identity(), lidar, 40.0);
  ASSERT_EQ(e.size(), 1u);  // pixel (2,2) has no LiDAR; the 45 m point is out of range
  EXPECT_NEAR(e[0], 0.5, 1e-9);
}

TEST(SummarizeErrors, MedianRmseMean) {
  const auto s = SummarizeErrors({1.0, 3.0, 2.0, 4.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.median_m, 2.5);
  EXPECT_DOUBLE_EQ(s.mean_abs_m, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse_m, std::sqrt(30.0 / 4.0));
  EXPECT_EQ(SummarizeErrors({}).count, 0u);
  EXPECT_DOUBLE_EQ(SummarizeErrors({3.0, 1.0, 2.0}).median_m, 2.0);
}

}  // namespace
}  // namespace semap
