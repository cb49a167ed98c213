// Rectified stereo calibration and the pinhole model used by every stage.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>

namespace semap {

// Transform naming: `a_from_b` maps coordinates expressed in frame b into frame a,
// e.g. p_world = world_from_cam * p_cam. Camera frames follow the KITTI/OpenCV convention:
// x right, y down, z forward. All translations are in metres.
using Pose3d = Eigen::Isometry3d;

// Rectified stereo pair: both cameras share the intrinsics; the right camera sits at +baseline_m along x.
struct StereoCalibration {
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
  double baseline_m = 0.0;  // distance between the optical centres, > 0
  int width_px = 0;
  int height_px = 0;

  // True when every value is finite and positive where it must be.
  bool IsValid() const;

  // depth_m = fx * baseline / disparity. Requires disparity_px > 0.
  double DepthFromDisparity(double disparity_px) const { return fx_px * baseline_m / disparity_px; }
  double DisparityFromDepth(double depth_m) const { return fx_px * baseline_m / depth_m; }

  // Pixel (u, v) of a point in the left camera frame; requires p_cam.z() > 0.
  Eigen::Vector2d Project(const Eigen::Vector3d& p_cam) const {
    return {fx_px * p_cam.x() / p_cam.z() + cx_px, fy_px * p_cam.y() / p_cam.z() + cy_px};
  }
  // Point in the left camera frame at pixel (u, v) and depth z (camera-frame z, not range).
  Eigen::Vector3d Unproject(double u_px, double v_px, double depth_m) const {
    return {(u_px - cx_px) * depth_m / fx_px, (v_px - cy_px) * depth_m / fy_px, depth_m};
  }
  bool InImage(const Eigen::Vector2d& uv_px) const {
    return uv_px.x() >= 0.0 && uv_px.y() >= 0.0 && uv_px.x() < width_px && uv_px.y() < height_px;
  }
};

// What a stereo rig's rectification adds to every disparity measured on its pairs (true = measured + At(v)):
// a constant (the right camera's principal point, or a yaw between the cameras, off by a fraction of a pixel)
// and a term that grows with the image row (a roll between the cameras, or a matching bias that differs
// between the road low in the image and the rest), zero at the principal point's row.
struct DisparityOffset {
  double constant_px = 0.0;
  double per_row_px = 0.0;  // the offset's change per unit of (v − cy) / fy, px
  double At(double v_px, const StereoCalibration& c) const {
    return constant_px + per_row_px * (v_px - c.cy_px) / c.fy_px;
  }
  bool IsZero() const { return constant_px == 0.0 && per_row_px == 0.0; }
};

// The residual vertical misalignment of a rectified pair: right row − left row at a left-image pixel, a
// quadratic in x = (u − W/2) / W and y = (v − H/2) / W (the image's centre and width; no calibration needed):
// Σ coefficients_px[k] · (1, x, y, x·y, x², y²)[k]. Measured on the images (engine/depth/row_alignment.h).
struct RowOffsets {
  static constexpr int kTerms = 6;
  std::array<double, kTerms> coefficients_px{};
  cv::Size image_size;
  int matches = 0;                  // the stereo matches the fit kept
  double median_residual_px = 0.0;  // their median |residual|
  double max_abs_px = 0.0;          // the largest |fitted offset| at those matches (not extrapolated)

  double At(double u_px, double v_px) const {
    const double w = image_size.width;
    const double x = (u_px - 0.5 * w) / w;
    const double y = (v_px - 0.5 * image_size.height) / w;
    const std::array<double, kTerms> t{1.0, x, y, x * y, x * x, y * y};
    double offset = 0.0;
    for (int k = 0; k < kTerms; ++k)
      offset += coefficients_px[static_cast<size_t>(k)] * t[static_cast<size_t>(k)];
    return offset;
  }
};

}  // namespace semap
