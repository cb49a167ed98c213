// A camera's depth map as the map's visibility votes read it (engine/map/internal/depth_votes.h).
#pragma once

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>

#include "engine/core/calibration.h"

namespace semap {

// Depth of a pixel whose ray is free up to the far range (sky: a ray that met nothing within max_depth_m).
inline constexpr float kFreeToFarRange = std::numeric_limits<float>::infinity();

// One camera's view, downsampled: `intrinsics` are those of `depth_m` (scaled to its resolution; the
// baseline is unused). Immutable once made, shared between the cloud and the map's window of stored views.
struct DepthView {
  StereoCalibration intrinsics;
  Pose3d world_from_cam = Pose3d::Identity();
  // CV_32F camera-frame z in metres; 0 = no depth (unmatched, out of range); kFreeToFarRange = free up to
  // max_depth_m along the ray.
  cv::Mat depth_m;
  // Full-resolution pixels (rays) that one pixel of depth_m stands for: the unit of the votes.
  double rays_per_pixel = 1.0;
  double max_depth_m = 0.0;  // the far range of kFreeToFarRange pixels

  bool empty() const { return depth_m.empty(); }
  // The depth at pixel (u, v) of depth_m (nearest), or 0 outside the image.
  float At(double u_px, double v_px) const {
    const int u = int(std::floor(u_px)), v = int(std::floor(v_px));
    if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) return 0.0f;
    return depth_m.at<float>(v, u);
  }
};

}  // namespace semap
