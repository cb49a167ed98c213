#include "engine/depth/depth_metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace semap {

DisparityMetrics& DisparityMetrics::operator+=(const DisparityMetrics& o) {
  gt_pixels += o.gt_pixels;
  estimated += o.estimated;
  outliers += o.outliers;
  return *this;
}

DisparityMetrics EvaluateDisparity(const cv::Mat& estimate_px, const cv::Mat& ground_truth_px,
                                   D1Thresholds thresholds) {
  if (estimate_px.type() != CV_32FC1 || ground_truth_px.type() != CV_32FC1 ||
      estimate_px.size() != ground_truth_px.size()) {
    throw std::invalid_argument("EvaluateDisparity: both maps must be CV_32F of the same size");
  }
  DisparityMetrics m;
  for (int v = 0; v < estimate_px.rows; ++v) {
    const float* e = estimate_px.ptr<float>(v);
    const float* g = ground_truth_px.ptr<float>(v);
    for (int u = 0; u < estimate_px.cols; ++u) {
      if (!(g[u] > 0.0f) || !std::isfinite(g[u])) continue;
      ++m.gt_pixels;
      if (!(e[u] > 0.0f) || !std::isfinite(e[u])) continue;
      ++m.estimated;
      const double err = std::abs(double(e[u]) - double(g[u]));
      if (err > thresholds.abs_px && err > thresholds.relative * g[u]) ++m.outliers;
    }
  }
  return m;
}

cv::Mat LidarDepthImage(const VelodyneScan& scan, const StereoCalibration& calibration, double max_depth_m) {
  cv::Mat depth = cv::Mat::zeros(calibration.height_px, calibration.width_px, CV_32F);
  for (const auto& p : scan.points_velo) {
    const Eigen::Vector3d p_cam = scan.cam_from_velo * p.head<3>().cast<double>();
    if (!(p_cam.z() > 0.0) || p_cam.z() > max_depth_m) continue;
    const Eigen::Vector2d uv = calibration.Project(p_cam);
    const long u = std::lround(uv.x());
    const long v = std::lround(uv.y());
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    float& d = depth.at<float>(static_cast<int>(v), static_cast<int>(u));
    if (d == 0.0f || p_cam.z() < d) d = static_cast<float>(p_cam.z());
  }
  return depth;
}

std::vector<double> DepthErrorsAgainstLidar(const LabelledCloud& cloud, const Pose3d& cam_from_world,
                                            const cv::Mat& lidar_depth, double max_depth_m) {
  if (lidar_depth.type() != CV_32FC1) throw std::invalid_argument("lidar depth must be CV_32F");
  std::vector<double> errors;
  if (cloud.pixels_px.size() != cloud.size()) return errors;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const long u = std::lround(cloud.pixels_px[i].x());
    const long v = std::lround(cloud.pixels_px[i].y());
    if (u < 0 || v < 0 || u >= lidar_depth.cols || v >= lidar_depth.rows) continue;
    const float z_lidar = lidar_depth.at<float>(static_cast<int>(v), static_cast<int>(u));
    if (!(z_lidar > 0.0f) || z_lidar > max_depth_m) continue;
    const double z = (cam_from_world * cloud.positions_world[i]).z();
    if (z > max_depth_m) continue;
    errors.push_back(std::abs(z - z_lidar));
  }
  return errors;
}

DepthErrorStats SummarizeErrors(std::vector<double> e) {
  DepthErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  const auto mid = e.begin() + static_cast<long>(e.size() / 2);
  std::nth_element(e.begin(), mid, e.end());
  s.median_m = *mid;
  if (e.size() % 2 == 0) s.median_m = 0.5 * (s.median_m + *std::max_element(e.begin(), mid));
  double sq = 0.0, abs_sum = 0.0;
  for (double x : e) {
    sq += x * x;
    abs_sum += x;
  }
  s.rmse_m = std::sqrt(sq / e.size());
  s.mean_abs_m = abs_sum / e.size();
  return s;
}

}  // namespace semap
