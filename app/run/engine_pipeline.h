// The streaming engine as a run's configuration assembles it: the frame source and the pipeline of stages
// (app/run/stream_run.h adds the sinks and runs it).
#pragma once

#include <memory>
#include <string>

#include "app/config/config.h"
#include "app/run/odometry_reader.h"
#include "engine/pipeline/pipeline.h"
#include "engine/pipeline/stages.h"
#include "io/frame_source.h"

namespace semap::app {

// The frame source of a streaming run: the dataset with config.input, except that Velodyne scans are not
// loaded (they serve evaluation only, so a missing one must not cost a frame).
std::unique_ptr<io::FrameSource> OpenStreamingSource(const Config& config, const std::string& dataset);

// The engine's stages on `source` as `config` says: SGBM + labels, `simplify` (or the configured windowed
// simplification when null), the incremental map. With `odometry` (its log not null), visual odometry runs in
// the reader as its plan says (OdometryReader). Sinks are the caller's to add.
std::unique_ptr<Pipeline> MakeEnginePipeline(const Config& config, std::unique_ptr<io::FrameSource> source,
                                             std::unique_ptr<SimplifyStage> simplify = nullptr,
                                             const RunOdometry* odometry = nullptr);

}  // namespace semap::app
