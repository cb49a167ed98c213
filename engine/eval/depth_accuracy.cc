#include "engine/eval/depth_accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/check.h"

namespace semap {

void DepthAccuracyOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (max_depth_m <= min_depth_m) {
    throw OptionError(*this, max_depth_m, "must be > " + KeyOf(*this, min_depth_m));
  }
}

DepthAccuracyOptions PaperProtocol(const DepthAccuracyOptions& strict) {
  DepthAccuracyOptions paper = strict;
  paper.max_depth_m = std::min(kPaperMaxDepthM, strict.max_depth_m);
  paper.max_abs_error_m = kPaperMaxAbsErrorM;
  return paper;
}

std::string ProtocolFilters(const DepthAccuracyOptions& options) {
  char text[128];
  if (options.max_abs_error_m > 0.0) {
    std::snprintf(text, sizeof(text), "reference depth %g-%g m, |error| <= %g m", options.min_depth_m,
                  options.max_depth_m, options.max_abs_error_m);
  } else {
    std::snprintf(text, sizeof(text), "reference depth %g-%g m, every error", options.min_depth_m,
                  options.max_depth_m);
  }
  return text;
}

cv::Mat LidarDepthImage(const VelodyneScan& scan, const StereoCalibration& calibration,
                        const DepthAccuracyOptions& options) {
  options.Check();
  SEMAP_ASSERT(calibration.IsValid());
  cv::Mat depth(calibration.height_px, calibration.width_px, CV_32F, cv::Scalar(0.0f));
  for (const auto& p : scan.points_velo) {
    const Eigen::Vector3d p_cam = scan.cam_from_velo * p.head<3>().cast<double>();
    if (!(p_cam.z() >= options.min_depth_m && p_cam.z() <= options.max_depth_m)) continue;
    const Eigen::Vector2d uv = calibration.Project(p_cam);
    const int u = static_cast<int>(std::lround(uv.x()));
    const int v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= calibration.width_px || v >= calibration.height_px) continue;
    float& d = depth.at<float>(v, u);
    if (d == 0.0f || p_cam.z() < d) d = static_cast<float>(p_cam.z());
  }
  return depth;
}

DepthAccuracyAccumulator::DepthAccuracyAccumulator(const DepthAccuracyOptions& options) : options_(options) {
  options_.Check();
}

void DepthAccuracyAccumulator::Add(const cv::Mat& reference, const cv::Mat& mesh) {
  SEMAP_ASSERT(reference.type() == CV_32F && mesh.type() == CV_32F && reference.size() == mesh.size());
  for (int y = 0; y < reference.rows; ++y) {
    const float* r = reference.ptr<float>(y);
    const float* m = mesh.ptr<float>(y);
    for (int x = 0; x < reference.cols; ++x) {
      if (!(r[x] >= options_.min_depth_m && r[x] <= options_.max_depth_m)) continue;
      ++reference_pixels_;
      if (!(m[x] > 0.0f) || !std::isfinite(m[x])) continue;
      const double e = static_cast<double>(m[x]) - static_cast<double>(r[x]);
      if (options_.max_abs_error_m > 0.0 && std::abs(e) > options_.max_abs_error_m) {
        ++outliers_;
        continue;
      }
      sum_sq_ += e * e;
      sum_abs_ += std::abs(e);
      sum_ += e;
      abs_errors_.push_back(static_cast<float>(std::abs(e)));
    }
  }
}

void DepthAccuracyAccumulator::Merge(const DepthAccuracyAccumulator& other) {
  reference_pixels_ += other.reference_pixels_;
  outliers_ += other.outliers_;
  sum_sq_ += other.sum_sq_;
  sum_abs_ += other.sum_abs_;
  sum_ += other.sum_;
  abs_errors_.insert(abs_errors_.end(), other.abs_errors_.begin(), other.abs_errors_.end());
}

DepthAccuracy DepthAccuracyAccumulator::Result() const {
  DepthAccuracy a;
  a.reference_pixels = reference_pixels_;
  const auto n = static_cast<std::int64_t>(abs_errors_.size());
  a.compared_pixels = n + outliers_;
  a.excluded_pixels = outliers_;
  a.completeness = reference_pixels_
                       ? static_cast<double>(a.compared_pixels) / static_cast<double>(reference_pixels_)
                       : 0.0;
  if (n == 0) return a;
  a.rmse_m = std::sqrt(sum_sq_ / static_cast<double>(n));
  a.mae_m = sum_abs_ / static_cast<double>(n);
  a.mean_error_m = sum_ / static_cast<double>(n);
  std::vector<float> e = abs_errors_;
  std::nth_element(e.begin(), e.begin() + n / 2, e.end());
  a.median_abs_m = e[static_cast<size_t>(n / 2)];
  return a;
}

}  // namespace semap
