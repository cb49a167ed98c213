// Rebuilds the mesh from an lcm-logger log of a semap run (snapshots + deltas).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/core/mesh.h"

namespace semap::io {

struct MeshLogReplay {
  Mesh mesh;                     // the mesh after the last message
  std::int64_t snapshots = 0;    // snapshot messages applied
  std::int64_t deltas = 0;       // delta messages applied
  std::int64_t sequence_gaps = 0;  // missing sequence numbers (lost messages)
  std::int64_t last_frame_id = -1;
  std::int64_t other_events = 0;   // events on other channels
};

// Reads every event of `log_path`; applies <prefix>MESH_SNAPSHOT (reset, then apply) and <prefix>MESH_DELTA
// messages in order. Throws FileError (io/mesh/ply_off.h) naming the path if it is missing or not an LCM log,
// std::runtime_error on an undecodable message.
MeshLogReplay ReplayMeshLog(const std::filesystem::path& log_path, const std::string& channel_prefix = "SEMAP_");

}  // namespace semap::io
