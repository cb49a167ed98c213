// One `semap map-sfm` run: an existing structure-from-motion / SLAM reconstruction through the Delaunay map,
// in one batch or keyframe by keyframe, into the run's sinks (mesh files, stats, LCM, progress).
#pragma once

#include <filesystem>

#include "app/config/config.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::app {

struct MapSfmRequest {
  std::filesystem::path input;  // a COLMAP model folder, an OpenMVG sfm_data.json or a SLAM JSON
  io::SfmFormat format = io::SfmFormat::kColmap;
  bool incremental = false;  // view by view as keyframes (default: one batch map)
  double progress_s = 1.0;   // seconds between progress lines
};

// Reads the reconstruction (points beyond the map's coordinate range are left out, with a warning), maps it
// as `config` says (config.map, config.simplify, config.input.class_map) and writes or publishes what
// config.output and config.lcm ask for; logs what it did. Throws io::FileError / io::ParseError naming the
// input, and what the sinks throw for an unusable output folder or LCM URL (before any mapping is done).
void MapSfm(const Config& config, const MapSfmRequest& request);

}  // namespace semap::app
