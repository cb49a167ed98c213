// A synthetic SfM/SLAM reconstruction with exact ground truth, for the io/sfm tests, `semap map-sfm` tests
// and bench/sfm_bench: keyframes drive along the analytic street corridor of the map tests
// (tests/engine/map/street_scene.h) looking forward (+y), with a small yaw wobble. Each keyframe brings
// `new_points_per_keyframe` points: random pixels of its pinhole image cast onto the surfaces within range
// (labelled road / building / car, coloured by label). The next keyframes observe a point again, at its
// projected pixel, while it is in their image, within range and not occluded (up to max_track_keyframes).
#pragma once

#include "io/sfm/sfm_reconstruction.h"
#include "tests/engine/map/street_scene.h"

namespace semap::test {

struct SfmStreetOptions {
  int keyframes = 20;
  double keyframe_step_m = 1.0;
  double first_keyframe_y_m = 0.0;
  int new_points_per_keyframe = 300;
  int max_track_keyframes = 10;  // later keyframes that may observe a point
  double max_range_m = 30.0;
  double noise_m = 0.0;  // isotropic Gaussian noise on the point positions (pixels stay exact)
  double yaw_wobble_rad = 0.05;
  bool labels = true;
  bool colours = true;
  // Pinhole camera (COLMAP SIMPLE_PINHOLE): ±45° horizontal, ±31° vertical.
  double focal_px = 500.0;
  int width_px = 1000;
  int height_px = 600;
  unsigned seed = 1;
};

// The street of the scene must be long enough for the keyframes and the range (see SfmStreetScene()).
io::SfmReconstruction MakeSfmStreet(const StreetScene& scene, const SfmStreetOptions& options);

// A StreetScene long enough for `options` (the street extends max_range_m beyond the last keyframe).
StreetScene SfmStreetScene(const SfmStreetOptions& options);

}  // namespace semap::test
