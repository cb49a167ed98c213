// `semap synth`: a generated street sequence written in the KITTI raw layout, with exact ground truth.
#pragma once

#include <filesystem>

#include "engine/sim/synth_options.h"

namespace semap::app {

// Builds the scene and trajectory of `options` (checked by the caller) and writes the sequence into `out`,
// logging progress every 2 s and, at the end, the frame rate, the Velodyne density and the class
// composition. Throws what the writer throws (io::FileError naming the file).
void GenerateSequence(const sim::SynthOptions& options, const std::filesystem::path& out);

}  // namespace semap::app
