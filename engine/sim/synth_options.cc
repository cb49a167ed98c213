#include "engine/sim/synth_options.h"

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
  CheckDeclaredRanges(*this);
  if (block_pitch_m < road_width_m + 2.0 * sidewalk_width_m + 20.0) {
    throw OptionError(*this, block_pitch_m, "must leave >= 20 m of lot inside the sidewalks");
  }
  if (lane_offset_m >= 0.5 * road_width_m - 1.0) {
    throw OptionError(*this, lane_offset_m, "must be below " + KeyOf(*this, road_width_m) + "/2 - 1");
  }
  if (!(turn_radius_m > lane_offset_m && turn_radius_m <= 0.5 * road_width_m + 10.0)) {
    throw OptionError(
        *this, turn_radius_m,
        "must be in (" + KeyOf(*this, lane_offset_m) + ", " + KeyOf(*this, road_width_m) + "/2 + 10]");
  }
  if (lidar_top_deg <= lidar_bottom_deg) {
    throw OptionError(*this, lidar_top_deg, "must be above " + KeyOf(*this, lidar_bottom_deg));
  }
  if (lidar_max_range_m <= lidar_min_range_m) {
    throw OptionError(*this, lidar_max_range_m, "must exceed " + KeyOf(*this, lidar_min_range_m));
  }
}

}  // namespace semap::sim
