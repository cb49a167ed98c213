// `semap synth`: a generated street sequence written in the KITTI raw layout, or a multi-view set in the
// Strecha layout, with exact ground truth.
#pragma once

#include <filesystem>

#include "engine/sim/multi_view_set.h"
#include "engine/sim/synth_options.h"

namespace semap::app {

// Builds the scene and trajectory of `options` (checked by the caller) and writes the sequence into `out`,
// logging progress every 2 s and, at the end, the frame rate, the Velodyne density and the class
// composition. Throws what the writer throws (io::FileError naming the file).
void GenerateSequence(const sim::SynthOptions& options, const std::filesystem::path& out);

// Builds the multi-view set of `set` (an ornate object before a wall, views on an arc; seed and photometric
// settings from `synth`) and writes it into `out` in the Strecha layout (io/synth/strecha_writer.h), logging
// the cameras' distances and, at the end, the class composition. Throws InvalidOption for invalid options and
// what the writer throws.
void GenerateMultiViewSet(const sim::SynthOptions& synth, const sim::MultiViewSetOptions& set,
                          const std::filesystem::path& out);

}  // namespace semap::app
