// Quality measures of the depth stage: KITTI's D1 disparity error against a ground-truth disparity map, and
// depth errors of the emitted points against a LiDAR scan.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "engine/core/frame.h"
#include "engine/core/labelled_cloud.h"

namespace semap {

struct DisparityMetrics {
  std::size_t gt_pixels = 0;        // pixels with ground truth (gt > 0)
  std::size_t estimated = 0;        // of those, pixels with an estimate (est > 0)
  std::size_t outliers = 0;         // estimated pixels with |err| > 3 px and > 5 % of the true disparity
  // KITTI D1-all: (outliers + gt pixels without an estimate) / gt pixels.
  double d1_all() const { return gt_pixels ? double(outliers + gt_pixels - estimated) / gt_pixels : 0.0; }
  // Outliers among the estimated pixels only.
  double d1_estimated() const { return estimated ? double(outliers) / estimated : 0.0; }
  // Share of ground-truth pixels that have an estimate.
  double density() const { return gt_pixels ? double(estimated) / gt_pixels : 0.0; }
  DisparityMetrics& operator+=(const DisparityMetrics& o);
};

// Thresholds of KITTI's D1 error.
struct D1Thresholds {
  double abs_px = 3.0;
  double relative = 0.05;
};

// Both maps CV_32F of the same size; ≤ 0 (or non-finite) = none. Throws std::invalid_argument otherwise.
DisparityMetrics EvaluateDisparity(const cv::Mat& estimate_px, const cv::Mat& ground_truth_px,
                                   D1Thresholds thresholds = {});

// The scan's points in the left camera (camera-frame z in (0, max_depth_m]) rasterised into a depth image
// (CV_32F, 0 = no return) of the calibration's size, keeping the nearest return per pixel.
cv::Mat LidarDepthImage(const VelodyneScan& scan, const StereoCalibration& calibration, double max_depth_m);

struct DepthErrorStats {
  std::size_t count = 0;     // points compared
  double median_m = 0.0;     // median |z_point − z_lidar|
  double rmse_m = 0.0;
  double mean_abs_m = 0.0;
};

// For every point of `cloud` whose pixel (pixels_px) has a LiDAR depth in `lidar_depth` and whose
// camera-frame z (via cam_from_world) is ≤ max_depth_m: |z_point − z_lidar|.
std::vector<double> DepthErrorsAgainstLidar(const LabelledCloud& cloud, const Pose3d& cam_from_world,
                                            const cv::Mat& lidar_depth, double max_depth_m);

// Median, RMSE and mean of absolute errors (empty input: count 0).
DepthErrorStats SummarizeErrors(std::vector<double> abs_errors);

}  // namespace semap
