// Renders a Scene through a rectified pinhole camera: colour, exact depth and labels.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "engine/core/calibration.h"
#include "engine/sim/scene.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

struct CameraImage {
  cv::Mat color;    // CV_8UC3, BGR, with blur, exposure, vignetting and noise applied
  cv::Mat depth_m;  // CV_32FC1: camera-frame z of the surface at each pixel centre, 0 = none (sky)
  cv::Mat labels;   // CV_8UC1: Cityscapes id of the surface at each pixel centre, 11 (sky) where none
};

// Per-image photometric settings.
struct Exposure {
  double gain = 1.0;             // multiplies the radiance
  std::uint64_t noise_seed = 0;  // seeds the image noise of this image
};

// Z-buffer rasteriser with per-pixel exact depth (ray-plane intersection at the pixel centre, pixel (u, v)
// centred at integer coordinates as in StereoCalibration::Project) and procedural shading. Holds a reference
// to the scene, which must outlive it. Render() is const and thread-safe.
class CameraRenderer {
 public:
  CameraRenderer(const Scene& scene, const SynthOptions& options);

  // Renders the view of a camera with pose `scene_from_cam` (x right, y down, z forward).
  CameraImage Render(const StereoCalibration& calibration, const Pose3d& scene_from_cam,
                     const Exposure& exposure) const;

  // Only the geometric buffers (depth, labels; no colour): for tests and ground-truth checks.
  CameraImage RenderGeometry(const StereoCalibration& calibration, const Pose3d& scene_from_cam) const;

 private:
  // Fills the nearest triangle index per pixel (-1 = none).
  cv::Mat Rasterize(const StereoCalibration& calibration, const Pose3d& scene_from_cam) const;

  const Scene& scene_;
  SynthOptions options_;
};

}  // namespace semap::sim
