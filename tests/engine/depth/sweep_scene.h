// A scene of textured planes and the tests' own renderer of it: grey views and exact depth, for the plane
// sweep's tests.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "engine/depth/plane_sweep.h"

namespace semap::sweep_scene {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr double kFocalPx = 300.0;

// The views' intrinsics: kFocalPx, the principal point near the image's centre.
Eigen::Matrix3d TestK();

// A textured planar rectangle: a random grey texture laid on the plane point + s · axis_s + t · axis_t.
struct TexturedPlane {
  Eigen::Vector3d point_world, axis_s, axis_t;  // axes orthonormal
  cv::Mat texture;                              // CV_32F grey levels
  double texels_per_m = 0.0;
};

// A blurred uniform random texture, size × size, grey levels in [20, 235].
cv::Mat RandomTexture(int size, std::uint64_t seed);

// The nearest plane the ray from `centre` along `direction` (world) meets inside its texture, as (distance
// along the direction, grey level); no hit: infinite distance.
std::pair<double, double> Trace(const std::vector<TexturedPlane>& scene, const Eigen::Vector3d& centre,
                                const Eigen::Vector3d& direction);

// A kWidth × kHeight view of the scene (2 × 2 samples per pixel, 0 where nothing is hit) and, when asked,
// the depth of the ray through each pixel's centre (camera-frame z; 0: no hit).
PlaneSweepView Render(const std::vector<TexturedPlane>& scene, const Pose3d& world_from_cam,
                      cv::Mat* depth_m = nullptr);

// A camera at `centre_world` looking at `target_world` (y of the camera roughly along world +y: down).
Pose3d LookAt(const Eigen::Vector3d& centre_world, const Eigen::Vector3d& target_world);

// A wall facing the reference camera (at the origin, looking along +z) at depth `depth_m`.
TexturedPlane Wall(double depth_m, std::uint64_t seed);

// The ground: the plane y = height_m (world, y down), textured over x in [-20, 20] m, z in [0.5, 41] m.
TexturedPlane Ground(double height_m, std::uint64_t seed);

// A camera at the origin pitched down by 10° (looking along +z, tilted towards +y).
Pose3d PitchedDown();

}  // namespace semap::sweep_scene
