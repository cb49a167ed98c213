// A rectified stereo calibration like KITTI odometry's (its left camera's intrinsics and baseline), for the
// odometry's tests on point sets.
#pragma once

#include "engine/core/calibration.h"

namespace semap::test {

inline StereoCalibration KittiOdometryCalibration() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 718.856;
  c.cx_px = 607.19;
  c.cy_px = 185.22;
  c.baseline_m = 0.537;
  c.width_px = 1241;
  c.height_px = 376;
  return c;
}

}  // namespace semap::test
