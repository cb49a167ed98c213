#include "engine/sim/synth_options.h"

#include <cmath>

#include "engine/core/check.h"

namespace semap::sim {

const char* ScenePresetName(ScenePreset preset) {
  switch (preset) {
    case ScenePreset::kUrban:
      return "urban";
    case ScenePreset::kVegetated:
      return "vegetated";
    case ScenePreset::kMixed:
      return "mixed";
  }
  return "?";
}

void SynthOptions::Check() const {
  SEMAP_CHECK_OPTION(num_frames >= 1 && num_frames <= 1000000, "num_frames", num_frames,
                     "must be in [1, 1e6]");
  SEMAP_CHECK_OPTION(speed_mps >= 0.0 && speed_mps <= 40.0, "speed_mps", speed_mps, "must be in [0, 40]");
  SEMAP_CHECK_OPTION(num_turns >= 0, "num_turns", num_turns, "must be >= 0");
  SEMAP_CHECK_OPTION(frame_rate_hz > 0.0 && frame_rate_hz <= 100.0, "frame_rate_hz", frame_rate_hz,
                     "must be in (0, 100]");
  SEMAP_CHECK_OPTION(body_wobble_rad >= 0.0 && body_wobble_rad < 0.1, "body_wobble_rad", body_wobble_rad,
                     "must be in [0, 0.1)");
  SEMAP_CHECK_OPTION(road_width_m >= 6.0, "road_width_m", road_width_m, "must be >= 6");
  SEMAP_CHECK_OPTION(sidewalk_width_m >= 1.0, "sidewalk_width_m", sidewalk_width_m, "must be >= 1");
  SEMAP_CHECK_OPTION(block_pitch_m >= road_width_m + 2.0 * sidewalk_width_m + 20.0, "block_pitch_m",
                     block_pitch_m, "must leave >= 20 m of lot inside the sidewalks");
  SEMAP_CHECK_OPTION(curb_height_m >= 0.0 && curb_height_m <= 0.5, "curb_height_m", curb_height_m,
                     "must be in [0, 0.5]");
  SEMAP_CHECK_OPTION(lane_offset_m >= 0.0 && lane_offset_m < 0.5 * road_width_m - 1.0, "lane_offset_m",
                     lane_offset_m, "must be in [0, road_width/2 - 1)");
  SEMAP_CHECK_OPTION(turn_radius_m > lane_offset_m && turn_radius_m <= 0.5 * road_width_m + 10.0,
                     "turn_radius_m", turn_radius_m, "must be in (lane_offset, road_width/2 + 10]");
  SEMAP_CHECK_OPTION(content_distance_m > 0.0, "content_distance_m", content_distance_m, "must be > 0");
  SEMAP_CHECK_OPTION(image_width_px >= 16 && image_width_px <= 8192, "image_width_px", image_width_px,
                     "must be in [16, 8192]");
  SEMAP_CHECK_OPTION(image_height_px >= 16 && image_height_px <= 8192, "image_height_px", image_height_px,
                     "must be in [16, 8192]");
  SEMAP_CHECK_OPTION(fx_px > 0.0 && fy_px > 0.0, "fx_px", fx_px, "focal lengths must be > 0");
  SEMAP_CHECK_OPTION(baseline_m > 0.0, "baseline_m", baseline_m, "must be > 0");
  SEMAP_CHECK_OPTION(near_m > 0.0, "near_m", near_m, "must be > 0");
  SEMAP_CHECK_OPTION(image_noise_sigma >= 0.0, "image_noise_sigma", image_noise_sigma, "must be >= 0");
  SEMAP_CHECK_OPTION(blur_sigma_px >= 0.0 && blur_sigma_px <= 5.0, "blur_sigma_px", blur_sigma_px,
                     "must be in [0, 5]");
  SEMAP_CHECK_OPTION(right_exposure_gain > 0.5 && right_exposure_gain < 2.0, "right_exposure_gain",
                     right_exposure_gain, "must be in (0.5, 2)");
  SEMAP_CHECK_OPTION(exposure_variation >= 0.0 && exposure_variation < 0.5, "exposure_variation",
                     exposure_variation, "must be in [0, 0.5)");
  SEMAP_CHECK_OPTION(vignetting >= 0.0 && vignetting < 1.0, "vignetting", vignetting, "must be in [0, 1)");
  SEMAP_CHECK_OPTION(lidar_beams >= 1 && lidar_beams <= 256, "lidar_beams", lidar_beams,
                     "must be in [1, 256]");
  SEMAP_CHECK_OPTION(lidar_azimuth_steps >= 8 && lidar_azimuth_steps <= 20000, "lidar_azimuth_steps",
                     lidar_azimuth_steps, "must be in [8, 20000]");
  SEMAP_CHECK_OPTION(lidar_top_deg > lidar_bottom_deg && lidar_top_deg < 90.0 && lidar_bottom_deg > -90.0,
                     "lidar_top_deg", lidar_top_deg, "must be above lidar_bottom_deg, both within (-90, 90)");
  SEMAP_CHECK_OPTION(lidar_min_range_m >= 0.0 && lidar_max_range_m > lidar_min_range_m, "lidar_max_range_m",
                     lidar_max_range_m, "must exceed lidar_min_range_m >= 0");
  SEMAP_CHECK_OPTION(lidar_range_noise_m >= 0.0 && lidar_range_noise_m < 1.0, "lidar_range_noise_m",
                     lidar_range_noise_m, "must be in [0, 1)");
  SEMAP_CHECK_OPTION(std::abs(origin_latitude_deg) < 80.0, "origin_latitude_deg", origin_latitude_deg,
                     "must be within (-80, 80) (Mercator)");
  SEMAP_CHECK_OPTION(std::abs(origin_longitude_deg) <= 180.0, "origin_longitude_deg", origin_longitude_deg,
                     "must be within [-180, 180]");
  SEMAP_CHECK_OPTION(std::isfinite(origin_altitude_m), "origin_altitude_m", origin_altitude_m,
                     "must be finite");
  SEMAP_CHECK_OPTION(std::isfinite(origin_heading_deg), "origin_heading_deg", origin_heading_deg,
                     "must be finite");
}

}  // namespace semap::sim
