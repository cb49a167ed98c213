// Options of the synthetic street-sequence generator (procedural world, stereo camera, Velodyne-like
// scanner).
#pragma once

#include <cstdint>

namespace semap::sim {

// Scene composition: which frontage types line the streets and how many trees, bushes and cars.
enum class ScenePreset { kUrban, kVegetated, kMixed };

const char* ScenePresetName(ScenePreset preset);

// Every parameter of a generated sequence. The same options (seed included) give byte-identical output.
// Defaults give a KITTI-like sequence: 1242x375 images, fx 721.5 px, 0.54 m baseline, 10 Hz, HDL-64-like
// scans.
struct SynthOptions {
  // --- Sequence -------------------------------------------------------------------------------------
  ScenePreset preset = ScenePreset::kUrban;
  // Number of frames to generate.
  int num_frames = 100;
  // Seed of every random choice (scene, trajectory, noise).
  std::uint64_t seed = 1;
  // Vehicle speed in m/s (KITTI residential drives: 5-10 m/s).
  double speed_mps = 8.0;
  // Number of 90-degree turns at intersections along the drive (fewer when the drive is too short).
  int num_turns = 1;
  // Frame rate of cameras and scanner (KITTI: 10 Hz).
  double frame_rate_hz = 10.0;
  // Amplitude of the small roll/pitch oscillation of the vehicle body (radians).
  double body_wobble_rad = 0.004;

  // --- World layout (Manhattan grid of blocks) ---------------------------------------------------------
  // Distance between parallel street centre lines (block pitch).
  double block_pitch_m = 70.0;
  // Width of the carriageway (kerb to kerb).
  double road_width_m = 12.0;
  // Width of the sidewalk ring around each block.
  double sidewalk_width_m = 3.5;
  // Height of the sidewalk above the road (the curb).
  double curb_height_m = 0.12;
  // Lateral offset of the vehicle to the right of the street centre line.
  double lane_offset_m = 2.0;
  // Radius of the arcs driven through intersections.
  double turn_radius_m = 6.0;
  // Blocks closer than this to the drive get full-detail content.
  double content_distance_m = 60.0;

  // --- Camera (rectified stereo pair, the left one is KITTI's cam 2) --------------------------------------
  int image_width_px = 1242;
  int image_height_px = 375;
  double fx_px = 721.5377;
  double fy_px = 721.5377;
  double cx_px = 609.5593;
  double cy_px = 172.854;
  double baseline_m = 0.54;
  // Nearest rendered depth (camera z).
  double near_m = 0.3;
  // Standard deviation of the additive Gaussian image noise, in 8-bit grey levels.
  double image_noise_sigma = 2.0;
  // Standard deviation of the Gaussian optical blur, in pixels (0 = none).
  double blur_sigma_px = 0.6;
  // Exposure (gain) of the right camera relative to the left one.
  double right_exposure_gain = 0.94;
  // Relative frame-to-frame exposure variation (slow, both cameras).
  double exposure_variation = 0.06;
  // Strength of the radial vignetting (relative brightness loss in the image corners).
  double vignetting = 0.25;

  // --- Scanner (Velodyne HDL-64E-like, one instantaneous scan per frame) ---------------------------------
  int lidar_beams = 64;
  // Rays per beam and revolution.
  int lidar_azimuth_steps = 2048;
  // Elevation of the top and bottom beam in degrees.
  double lidar_top_deg = 2.0;
  double lidar_bottom_deg = -24.8;
  double lidar_min_range_m = 2.0;
  double lidar_max_range_m = 120.0;
  // Standard deviation of the Gaussian range noise; 0 gives exact points (exactness tests).
  double lidar_range_noise_m = 0.02;

  // --- Geo-reference of the first frame (OXTS) -------------------------------------------------------------
  double origin_latitude_deg = 49.0;
  double origin_longitude_deg = 8.4;
  double origin_altitude_m = 115.0;
  // Heading of the first street, degrees counter-clockwise from East.
  double origin_heading_deg = 30.0;

  void Check() const;
};

}  // namespace semap::sim
