// `semap lcm-mesh`: the mesh a run published over LCM, rebuilt from a log or live, written and reported.
#pragma once

#include <filesystem>
#include <string>

#include "io/lcm/lcm_log.h"

namespace semap::app {

// Logs what the replay of `source` (a log file or an LCM URL) met (damaged bytes, skipped messages), writes
// its mesh to `out` (.off, else PLY; ASCII PLY with `ascii`) and reports the run's state. Returns false,
// having logged why, when no triangle was rebuilt (nothing written) or when blocks are missing (the mesh
// written is incomplete).
bool WriteReplayedMesh(const std::string& source, const io::MeshReplay& replay,
                       const std::filesystem::path& out, bool ascii);

}  // namespace semap::app
