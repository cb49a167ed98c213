#include "engine/depth/stereo_depth.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "engine/core/check.h"
#include "engine/depth/internal/disparity_fill.h"
#include "engine/depth/row_alignment.h"

namespace semap {
namespace {

// OpenCV's fixed-point disparity scale (CV_16S maps hold disparity · 16).
constexpr float kSgbmDisparityScale = 16.0f;
constexpr int kDisparityMultiple = DepthOptions::kDisparityMultiple;

int ToOpenCvMode(SgbmMode mode) {
  switch (mode) {
    case SgbmMode::kSgbm:
      return cv::StereoSGBM::MODE_SGBM;
    case SgbmMode::kHh:
      return cv::StereoSGBM::MODE_HH;
    case SgbmMode::kThreeWay:
      return cv::StereoSGBM::MODE_SGBM_3WAY;
    case SgbmMode::kHh4:
      return cv::StereoSGBM::MODE_HH4;
  }
  return cv::StereoSGBM::MODE_SGBM;
}

std::string Describe(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows) + " with " + std::to_string(m.channels()) +
         " channel(s), depth " + std::to_string(m.depth());
}

void CheckPair(const cv::Mat& left, const cv::Mat& right) {
  if (left.empty() || right.empty()) {
    throw std::invalid_argument(std::string("stereo pair: the ") + (left.empty() ? "left" : "right") +
                                " image is empty");
  }
  if (left.size() != right.size()) {
    throw std::invalid_argument("stereo pair: left image is " + Describe(left) + " but right image is " +
                                Describe(right) + " (sizes differ)");
  }
  if (left.type() != right.type()) {
    throw std::invalid_argument("stereo pair: left image is " + Describe(left) + " but right image is " +
                                Describe(right) + " (grayscale/colour or depth mix)");
  }
  if (left.type() != CV_8UC1 && left.type() != CV_8UC3) {
    throw std::invalid_argument("stereo pair: images must be 8-bit grayscale or 8-bit 3-channel BGR, got " +
                                Describe(left));
  }
}

cv::Mat RunSgbm(const DepthOptions& o, const cv::Mat& left, const cv::Mat& right, int num_disparities) {
  // An image no wider than the search range has no pixel with a full search range; OpenCV 4.6's 3-way
  // matcher aborts the process on it (an exception inside its parallel loop): no disparity instead.
  if (left.cols <= num_disparities) return cv::Mat::zeros(left.size(), CV_32F);
  const int channels = left.channels();
  const int area = o.block_size * o.block_size;
  const int p1 = o.p1 > 0 ? o.p1 : 8 * channels * area;
  const int p2 = o.p2 > 0 ? o.p2 : 32 * channels * area;
  auto sgbm = cv::StereoSGBM::create(/*minDisparity=*/0, num_disparities, o.block_size, p1, p2,
                                     o.disp12_max_diff_px, o.pre_filter_cap, o.uniqueness_ratio,
                                     o.speckle_window_size, o.speckle_range_px, ToOpenCvMode(o.mode));
  cv::Mat disparity_fixed;
  sgbm->compute(left, right, disparity_fixed);
  cv::Mat disparity;
  disparity_fixed.convertTo(disparity, CV_32F, 1.0 / kSgbmDisparityScale);
  // OpenCV marks invalid pixels with (minDisparity - 1); a zero disparity is a point at infinity: both
  // invalid.
  cv::threshold(disparity, disparity, 0.0, 0.0, cv::THRESH_TOZERO);
  return disparity;
}

// Disparity of the right image (positive values, right pixel u matches left pixel u + d): SGBM on the
// mirrored pair (mirrored right as the reference image).
cv::Mat RunSgbmRight(const DepthOptions& o, const cv::Mat& left, const cv::Mat& right, int num_disparities) {
  cv::Mat left_flipped, right_flipped, disparity;
  cv::flip(left, left_flipped, 1);
  cv::flip(right, right_flipped, 1);
  cv::flip(RunSgbm(o, right_flipped, left_flipped, num_disparities), disparity, 1);
  return disparity;
}

// Invalidates the left pixels whose match in the right image does not map back within max_diff_px.
void LeftRightCheck(const cv::Mat& right_disparity, float max_diff_px, cv::Mat* left_disparity) {
  for (int v = 0; v < left_disparity->rows; ++v) {
    float* dl = left_disparity->ptr<float>(v);
    const float* dr = right_disparity.ptr<float>(v);
    for (int u = 0; u < left_disparity->cols; ++u) {
      if (!(dl[u] > 0.0f)) continue;
      const int ur = static_cast<int>(std::lround(u - dl[u]));
      if (ur < 0 || !(dr[ur] > 0.0f) || std::abs(dr[ur] - dl[u]) > max_diff_px) dl[u] = 0.0f;
    }
  }
}

// RunSgbmRight on the pair at half resolution, its disparity brought back to `size` in full-resolution px:
// the right image's disparity for a left-right check at a quarter of the pixels.
cv::Mat RunSgbmRightHalf(const DepthOptions& o, const cv::Mat& left, const cv::Mat& right,
                         int num_disparities) {
  cv::Mat left_half, right_half, disparity;
  cv::resize(left, left_half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::resize(right, right_half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  const int half_disparities =
      std::max(kDisparityMultiple, num_disparities / 2 / kDisparityMultiple * kDisparityMultiple);
  cv::resize(RunSgbmRight(o, left_half, right_half, half_disparities), disparity, left.size(), 0.0, 0.0,
             cv::INTER_NEAREST);
  return disparity * 2.0f;
}

cv::Mat MatchPair(const DepthOptions& o, const cv::Mat& left, const cv::Mat& right, int num_disparities) {
  cv::Mat disparity = RunSgbm(o, left, right, num_disparities);
  if (o.left_right_max_diff_px >= 0.0f) {
    const cv::Mat right_disparity = o.left_right_half_resolution
                                        ? RunSgbmRightHalf(o, left, right, num_disparities)
                                        : RunSgbmRight(o, left, right, num_disparities);
    LeftRightCheck(right_disparity, o.left_right_max_diff_px, &disparity);
  }
  return disparity;
}

}  // namespace

const char* SgbmModeName(SgbmMode mode) {
  switch (mode) {
    case SgbmMode::kSgbm:
      return "sgbm";
    case SgbmMode::kHh:
      return "hh";
    case SgbmMode::kThreeWay:
      return "3way";
    case SgbmMode::kHh4:
      return "hh4";
  }
  return "?";
}

void DepthOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (p1 != 0 && p2 != 0 && p2 <= p1)
    throw OptionError(*this, p2, "must be greater than " + KeyOf(*this, p1));
  if (max_depth_m <= min_depth_m) {
    throw OptionError(*this, max_depth_m, "must be greater than " + KeyOf(*this, min_depth_m));
  }
}

StereoDepth::StereoDepth(const DepthOptions& options) : options_(options) { options_.Check(); }

DisparityResult StereoDepth::Compute(const cv::Mat& left, const cv::Mat& right,
                                     const RowOffsets* row_offsets) const {
  CheckPair(left, right);
  const DepthOptions& o = options_;
  DisparityResult result;
  cv::Mat right_rows = right;  // the right image, its rows lined up with the left's when align_rows
  if (o.align_rows) {
    std::optional<RowOffsets> measured;
    if (row_offsets == nullptr) {
      measured = FitRowOffsets(left, right);
      if (measured) row_offsets = &*measured;
    }
    if (row_offsets != nullptr && row_offsets->max_abs_px >= o.align_rows_min_px &&
        row_offsets->image_size == right.size()) {
      right_rows = AlignRows(right, *row_offsets);
      result.rows_aligned_px = row_offsets->max_abs_px;
    }
  }
  if (!o.half_resolution) {
    result.disparity_px = MatchPair(o, left, right_rows, o.num_disparities);
  } else {
    cv::Mat left_half, right_half;
    cv::resize(left, left_half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    cv::resize(right_rows, right_half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    const int half_range = std::max(kDisparityMultiple, (o.num_disparities / 2 + kDisparityMultiple - 1) /
                                                            kDisparityMultiple * kDisparityMultiple);
    if (left_half.empty()) {
      result.disparity_px = cv::Mat::zeros(left.size(), CV_32F);
    } else {
      const cv::Mat half = MatchPair(o, left_half, right_half, half_range);
      // Back to full resolution: nearest neighbour (never mixes valid and invalid pixels), values × 2.
      cv::resize(half, result.disparity_px, left.size(), 0.0, 0.0, cv::INTER_NEAREST);
      result.disparity_px *= 2.0f;
    }
  }
  result.confidence = cv::Mat(left.size(), CV_32F);
  depth_internal::FillDisparity(o.fill_max_gap_px, o.fill_left_border ? o.num_disparities : 0,
                                o.filled_confidence, &result.disparity_px, &result.confidence);
  return result;
}

cv::Mat StereoDepth::ComputeDisparity(const cv::Mat& left, const cv::Mat& right) const {
  return Compute(left, right).disparity_px;
}

cv::Mat DepthMapFromDisparity(const cv::Mat& disparity_px, const StereoCalibration& calibration) {
  cv::Mat depth_m = cv::Mat::zeros(disparity_px.size(), CV_32FC1);
  for (int v = 0; v < disparity_px.rows; ++v) {
    const float* d = disparity_px.ptr<float>(v);
    float* z = depth_m.ptr<float>(v);
    for (int u = 0; u < disparity_px.cols; ++u) {
      if (d[u] > 0.0f) z[u] = static_cast<float>(calibration.DepthFromDisparity(d[u]));
    }
  }
  return depth_m;
}

LabelledCloud StereoDepth::ToCloud(const Frame& frame, const cv::Mat& disparity_px,
                                   const cv::Mat& confidence) const {
  const DepthOptions& o = options_;
  const cv::Mat& image = frame.left;
  if (disparity_px.empty() || disparity_px.type() != CV_32FC1) {
    throw std::invalid_argument("ToCloud: the disparity must be a non-empty CV_32F image, got " +
                                Describe(disparity_px));
  }
  if (image.size() != disparity_px.size() || (image.type() != CV_8UC1 && image.type() != CV_8UC3)) {
    throw std::invalid_argument("ToCloud: frame " + std::to_string(frame.id) + " left image is " +
                                Describe(image) + ", expected 8-bit grey or BGR of the disparity's size " +
                                Describe(disparity_px));
  }
  if (!confidence.empty() && (confidence.size() != disparity_px.size() || confidence.type() != CV_32FC1)) {
    throw std::invalid_argument("ToCloud: the confidence must be CV_32F of the disparity's size, got " +
                                Describe(confidence));
  }
  if (!frame.calibration.IsValid()) {
    throw std::invalid_argument("ToCloud: frame " + std::to_string(frame.id) + " has an invalid calibration");
  }
  const StereoCalibration& calib = frame.calibration;
  const Pose3d world_from_cam = frame.world_from_cam.value_or(Pose3d::Identity());
  // Depth range → disparity range: z in [min, max] ⇔ d in [fB / max, fB / min].
  // (Disparities corrected by the frame's offset.)
  const double min_disparity = calib.DisparityFromDepth(o.max_depth_m);
  const double max_disparity = calib.DisparityFromDepth(o.min_depth_m);

  LabelledCloud cloud;
  cloud.camera_centers_world.push_back(world_from_cam.translation());
  cloud.camera_frame_ids.push_back(frame.id);
  const bool colour = image.channels() == 3;
  const int stride = o.half_resolution ? 2 * o.pixel_stride : o.pixel_stride;
  for (int v = 0; v < disparity_px.rows; v += stride) {
    const float offset_px = static_cast<float>(frame.disparity_offset.At(v, calib));
    const float* d_row = disparity_px.ptr<float>(v);
    const float* c_row = confidence.empty() ? nullptr : confidence.ptr<float>(v);
    const std::uint8_t* img_row = image.ptr<std::uint8_t>(v);
    for (int u = 0; u < disparity_px.cols; u += stride) {
      if (!std::isfinite(d_row[u]) || d_row[u] <= 0.0f) continue;  // no disparity measured
      const float d = d_row[u] + offset_px;
      if (d <= 0.0f || d < min_disparity || d > max_disparity) continue;
      const float c = c_row ? c_row[u] : 1.0f;
      if (!(c >= o.min_point_confidence)) continue;
      const double z = calib.DepthFromDisparity(d);
      if (z < o.min_depth_m || z > o.max_depth_m) continue;  // rounding at the range ends
      cloud.positions_world.push_back(world_from_cam * calib.Unproject(u, v, z));
      cloud.pixels_px.emplace_back(static_cast<float>(u), static_cast<float>(v));
      if (colour) {
        const std::uint8_t* bgr = img_row + 3 * u;
        cloud.colors_rgb.push_back({bgr[2], bgr[1], bgr[0]});
      } else {
        cloud.colors_rgb.push_back({img_row[u], img_row[u], img_row[u]});
      }
      cloud.confidence.push_back(c);
    }
  }
  cloud.camera_index.assign(cloud.size(), 0);
  if (o.max_points_per_frame > 0 && cloud.size() > static_cast<size_t>(o.max_points_per_frame)) {
    // Uniform decimation to exactly the budget: keep point i when floor(i·k/n) steps.
    const size_t n = cloud.size();
    const size_t k = static_cast<size_t>(o.max_points_per_frame);
    std::vector<std::uint32_t> keep;
    keep.reserve(k);
    for (size_t j = 0; j < k; ++j) keep.push_back(static_cast<std::uint32_t>(j * n / k));
    cloud = cloud.Subset(keep);
  }
  return cloud;
}

DepthView StereoDepth::ToDepthView(const Frame& frame, const cv::Mat& disparity_px,
                                   const cv::Mat& confidence) const {
  const DepthOptions& o = options_;
  if (disparity_px.empty() || disparity_px.type() != CV_32FC1 ||
      (!confidence.empty() && (confidence.size() != disparity_px.size() || confidence.type() != CV_32FC1))) {
    throw std::invalid_argument(
        "ToDepthView: expected a CV_32F disparity (and confidence of its size), got " +
        Describe(disparity_px));
  }
  if (!frame.calibration.IsValid()) {
    throw std::invalid_argument("ToDepthView: frame " + std::to_string(frame.id) +
                                " has an invalid calibration");
  }
  const StereoCalibration& calib = frame.calibration;
  const int s = o.vote_stride_px;
  DepthView view;
  view.world_from_cam = frame.world_from_cam.value_or(Pose3d::Identity());
  view.rays_per_pixel = double(s) * double(s);
  view.max_depth_m = o.max_depth_m;
  view.depth_m = cv::Mat::zeros((disparity_px.rows + s - 1) / s, (disparity_px.cols + s - 1) / s, CV_32F);
  // View pixel (i, j) is full-resolution pixel (i·s, j·s): u_full = s · u_view, so the intrinsics scale by
  // 1/s with the principal point at c / s.
  view.intrinsics = calib;
  view.intrinsics.fx_px = calib.fx_px / s;
  view.intrinsics.fy_px = calib.fy_px / s;
  view.intrinsics.cx_px = calib.cx_px / s;
  view.intrinsics.cy_px = calib.cy_px / s;
  view.intrinsics.width_px = view.depth_m.cols;
  view.intrinsics.height_px = view.depth_m.rows;
  for (int j = 0; j < view.depth_m.rows; ++j) {
    const float offset_px = static_cast<float>(frame.disparity_offset.At(j * s, calib));
    float* out = view.depth_m.ptr<float>(j);
    const float* d_row = disparity_px.ptr<float>(j * s);
    const float* c_row = confidence.empty() ? nullptr : confidence.ptr<float>(j * s);
    for (int i = 0; i < view.depth_m.cols; ++i) {
      if (!std::isfinite(d_row[i * s]) || d_row[i * s] <= 0.0f) continue;  // no disparity measured
      const float d = d_row[i * s] + offset_px;
      if (d <= 0.0f) continue;
      if (c_row && !(c_row[i * s] >= o.min_point_confidence)) continue;
      const double z = calib.DepthFromDisparity(d);
      if (z >= o.min_depth_m && z <= o.max_depth_m) out[i] = float(z);
    }
  }
  return view;
}

LabelledCloud StereoDepth::Process(const Frame& frame) const {
  const DisparityResult r =
      Compute(frame.left, frame.right, frame.row_offsets ? &*frame.row_offsets : nullptr);
  LabelledCloud cloud = ToCloud(frame, r.disparity_px, r.confidence);
  cloud.camera_views = {std::make_shared<const DepthView>(ToDepthView(frame, r.disparity_px, r.confidence))};
  return cloud;
}

}  // namespace semap
