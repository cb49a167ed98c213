// An analytic street corridor with exact ground truth for the map tests: ground plane z = 0, two walls at
// x = ±half_width, a box (a parked car) on the ground; cameras drive along +y at a fixed height, looking +y.
// World frame: x right, y forward, z up.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "engine/core/labelled_cloud.h"

namespace semap::test {

struct StreetScene {
  double half_width_m = 6.0;
  double wall_height_m = 8.0;
  double length_m = 120.0;  // y in [-10, length - 10]
  Eigen::Vector3d box_min{1.5, 18.0, 0.0};
  Eigen::Vector3d box_max{3.5, 22.0, 1.5};
  double camera_height_m = 1.6;

  // Exact distance from p to the nearest surface.
  double Distance(const Eigen::Vector3d& p) const;
  // First hit of the ray origin + t·dir (t > 0), with the label of the surface hit (1 road, 3 building, 14
  // car).
  std::optional<std::pair<double, Label>> Cast(const Eigen::Vector3d& origin,
                                               const Eigen::Vector3d& dir) const;
  Eigen::Vector3d CameraCenter(double y_m) const { return {0.0, y_m, camera_height_m}; }
};

struct StreetSamplingOptions {
  int num_cameras = 10;
  double first_camera_y_m = 0.0;
  double camera_step_m = 1.0;
  int rays_x = 60;  // samples per image row (a pinhole image of ±45° horizontal, ±30° vertical)
  int rays_z = 40;
  double max_range_m = 30.0;
  double noise_m = 0.0;  // isotropic Gaussian noise added to each point (seeded)
  unsigned seed = 1;
};

// One point per ray that hits the scene within range, with its camera (camera_index) and label.
LabelledCloud SampleStreet(const StreetScene& scene, const StreetSamplingOptions& options);

// One frame of the street seen by a 96×64 pinhole camera at y_m looking +y (±45° wide), as the pipeline's
// depth stage gives it: its exact depth view (rays that hit nothing are sky: free to the far range) and a
// point at every stride-th pixel.
LabelledCloud StreetDepthFrame(const StreetScene& scene, double y_m, int stride);

}  // namespace semap::test
