// Options of the synthetic street-sequence generator (procedural world, stereo camera, Velodyne-like
// scanner).
#pragma once

#include <cstdint>

#include "engine/core/options.h"

namespace semap::sim {

// Scene composition: which frontage types line the streets and how many trees, bushes and cars.
enum class ScenePreset { kUrban, kVegetated, kMixed };

const char* ScenePresetName(ScenePreset preset);

// Every parameter of a generated sequence. The same options (seed included) give byte-identical output.
// Defaults give a KITTI-like sequence: 1242x375 images, fx 721.5 px, 0.54 m baseline, 10 Hz, HDL-64-like
// scans.
struct SynthOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  // --- Sequence -------------------------------------------------------------------------------------
  ScenePreset preset = ScenePreset::kUrban;
  int num_frames = 100;
  std::uint64_t seed = 1;
  double speed_mps = 8.0;
  int num_turns = 1;
  double frame_rate_hz = 10.0;
  double body_wobble_rad = 0.004;

  // --- World layout (Manhattan grid of blocks) ---------------------------------------------------------
  double block_pitch_m = 70.0;
  double road_width_m = 12.0;
  double sidewalk_width_m = 3.5;
  double curb_height_m = 0.12;
  double lane_offset_m = 2.0;
  double turn_radius_m = 6.0;
  double content_distance_m = 60.0;

  // --- Camera (rectified stereo pair, the left one is KITTI's cam 2) --------------------------------------
  int image_width_px = 1242;
  int image_height_px = 375;
  double fx_px = 721.5377;
  double fy_px = 721.5377;
  double cx_px = 609.5593;
  double cy_px = 172.854;
  double baseline_m = 0.54;
  double near_m = 0.3;
  double image_noise_sigma = 2.0;
  double blur_sigma_px = 0.6;
  double right_exposure_gain = 0.94;
  double exposure_variation = 0.06;
  double vignetting = 0.25;

  // --- Scanner (Velodyne HDL-64E-like, one instantaneous scan per frame) ---------------------------------
  int lidar_beams = 64;
  int lidar_azimuth_steps = 2048;
  double lidar_top_deg = 2.0;
  double lidar_bottom_deg = -24.8;
  double lidar_min_range_m = 2.0;
  double lidar_max_range_m = 120.0;
  double lidar_range_noise_m = 0.02;

  // --- Geo-reference of the first frame (OXTS) -------------------------------------------------------------
  double origin_latitude_deg = 49.0;
  double origin_longitude_deg = 8.4;
  double origin_altitude_m = 115.0;
  double origin_heading_deg = 30.0;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Enum("preset", &preset,
           {{"urban", ScenePreset::kUrban},
            {"vegetated", ScenePreset::kVegetated},
            {"mixed", ScenePreset::kMixed}},
           "scene composition: urban (long facades, wide ground), vegetated (trees, bushes, cars), mixed");
    v.Field("num_frames", &num_frames, "number of frames to generate", In(1, 1000000));
    v.Field(
        "seed", &seed,
        "seed of every random choice (scene, trajectory, noise); the same seed gives byte-identical output");
    v.Field("speed_mps", &speed_mps, "vehicle speed in m/s (KITTI residential drives: 5-10)", In(0, 40));
    v.Field("num_turns", &num_turns, "90-degree turns at intersections (fewer if the drive is too short)",
            AtLeast(0));
    v.Field("frame_rate_hz", &frame_rate_hz, "camera and scanner rate in Hz (KITTI: 10)",
            Above(0).AtMost(100));
    v.Field("body_wobble_rad", &body_wobble_rad,
            "amplitude of the small roll/pitch oscillation of the vehicle body (rad)", AtLeast(0).Below(0.1));
    v.Field("block_pitch_m", &block_pitch_m,
            "distance between parallel street centre lines, the block pitch of the Manhattan grid (m); it "
            "leaves at least 20 m of lot inside the sidewalks");
    v.Field("road_width_m", &road_width_m, "carriageway width, kerb to kerb (m)", AtLeast(6));
    v.Field("sidewalk_width_m", &sidewalk_width_m, "width of the sidewalk ring around each block (m)",
            AtLeast(1));
    v.Field("curb_height_m", &curb_height_m, "sidewalk height above the road, the curb (m)", In(0, 0.5));
    v.Field("lane_offset_m", &lane_offset_m,
            "vehicle offset to the right of the street centre line (m), below road_width_m / 2 - 1",
            AtLeast(0));
    v.Field("turn_radius_m", &turn_radius_m,
            "radius of the arcs driven through intersections (m), in (lane_offset_m, road_width_m / 2 + 10]");
    v.Field("content_distance_m", &content_distance_m,
            "blocks closer than this to the drive get full-detail content (m)", Above(0));
    v.Field("image_width_px", &image_width_px, "image width (px)", In(16, 8192));
    v.Field("image_height_px", &image_height_px, "image height (px)", In(16, 8192));
    v.Field("fx_px", &fx_px, "focal length x (px)", Above(0));
    v.Field("fy_px", &fy_px, "focal length y (px)", Above(0));
    v.Field("cx_px", &cx_px, "principal point x (px)");
    v.Field("cy_px", &cy_px, "principal point y (px)");
    v.Field("baseline_m", &baseline_m, "stereo baseline (m)", Above(0));
    v.Field("near_m", &near_m, "nearest rendered depth, camera z (m)", Above(0));
    v.Field("image_noise_sigma", &image_noise_sigma,
            "standard deviation of the additive Gaussian image noise, in 8-bit grey levels", AtLeast(0));
    v.Field("blur_sigma_px", &blur_sigma_px, "standard deviation of the Gaussian optical blur (px), 0 = none",
            In(0, 5));
    v.Field("right_exposure_gain", &right_exposure_gain, "exposure of the right camera relative to the left",
            Above(0.5).Below(2));
    v.Field("exposure_variation", &exposure_variation,
            "relative slow frame-to-frame exposure drift (both cameras)", AtLeast(0).Below(0.5));
    v.Field("vignetting", &vignetting,
            "strength of the radial vignetting: relative brightness loss in the image corners",
            AtLeast(0).Below(1));
    v.Field("lidar_beams", &lidar_beams,
            "scanner beams (Velodyne HDL-64E: 64; one instantaneous scan per frame)", In(1, 256));
    v.Field("lidar_azimuth_steps", &lidar_azimuth_steps, "rays per beam and revolution", In(8, 20000));
    v.Field("lidar_top_deg", &lidar_top_deg, "elevation of the top beam (deg), above the bottom one",
            Above(-90).Below(90));
    v.Field("lidar_bottom_deg", &lidar_bottom_deg, "elevation of the bottom beam (deg)",
            Above(-90).Below(90));
    v.Field("lidar_min_range_m", &lidar_min_range_m, "minimum scanner range (m)", AtLeast(0));
    v.Field("lidar_max_range_m", &lidar_max_range_m, "maximum scanner range (m), beyond the minimum");
    v.Field("lidar_range_noise_m", &lidar_range_noise_m,
            "standard deviation of the Gaussian range noise (m); 0 = exact points (exactness tests)",
            AtLeast(0).Below(1));
    v.Field("origin_latitude_deg", &origin_latitude_deg, "latitude of the first frame (OXTS, deg; Mercator)",
            Above(-80).Below(80));
    v.Field("origin_longitude_deg", &origin_longitude_deg, "longitude of the first frame (OXTS, deg)",
            In(-180, 180));
    v.Field("origin_altitude_m", &origin_altitude_m, "altitude of the first frame (OXTS, m)");
    v.Field("origin_heading_deg", &origin_heading_deg,
            "heading of the first street, deg counter-clockwise from east");
  }

  void Check() const;
};

}  // namespace semap::sim
