// A CPU z-buffer rasteriser of a triangle mesh into a camera's depth map: the mesh side of the paper's
// accuracy measure. Exact up to float rounding: depth is interpolated as 1/z (perspective-correct) and
// triangles are clipped against the near plane.
#pragma once

#include <opencv2/core.hpp>

#include "engine/core/calibration.h"
#include "engine/core/mesh.h"

namespace semap {

struct DepthRenderOptions {
  // Triangles are clipped at this camera-frame z (m).
  double near_m = 0.1;
  void Check() const;
};

// Depth (camera-frame z, metres) of the nearest mesh surface at each pixel centre (integer pixel
// coordinates, the OpenCV/KITTI convention used by StereoCalibration::Project) of the camera described
// by `calibration` (intrinsics and image size) at pose `world_from_cam`; 0 where no triangle covers the
// pixel centre. CV_32F, height_px × width_px. Both faces of a triangle are rendered. Thread-safe.
cv::Mat RenderDepth(const Mesh& mesh, const StereoCalibration& calibration, const Pose3d& world_from_cam,
                    const DepthRenderOptions& options = {});

}  // namespace semap
