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

// The depth map of RenderDepth and, at each pixel, which triangle gave that depth.
struct DepthAndTriangles {
  cv::Mat depth;  // as RenderDepth
  cv::Mat
      triangle;  // CV_32S: index into mesh.triangles of the nearest triangle at the pixel centre, −1 = none
};

// RenderDepth, also telling which triangle each pixel's ray hits first (the error breakdown by triangle size
// and by the mesh's labels needs it). The depth equals RenderDepth's. Thread-safe.
DepthAndTriangles RenderDepthAndTriangles(const Mesh& mesh, const StereoCalibration& calibration,
                                          const Pose3d& world_from_cam,
                                          const DepthRenderOptions& options = {});

}  // namespace semap
