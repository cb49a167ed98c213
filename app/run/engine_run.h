// One in-process run of the streaming engine, shared by the subcommands that run it several times
// (`semap table`, `semap compare`): the same stages, sinks and summary as `semap run`, without LCM.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "app/eval/mesh_evaluation.h"
#include "app/run/odometry_reader.h"
#include "engine/core/mesh.h"
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

struct EngineRun {
  PipelineSummary summary;    // fps (frames / seconds of the whole incremental build), stage times
  Mesh mesh;                  // the final mesh (also written to config.output.dir)
  MeshEvaluation evaluation;  // against Velodyne (and exact depth for generated sequences)
};

// Streams `dataset` through the engine as `config` says (writing the mesh and the per-frame stats to
// config.output.dir), then evaluates the mesh on the same frames. Progress lines every `progress_s`
// seconds (0 = none). Throws what the run or the evaluation throws; a stage error that stopped the run
// is a std::runtime_error naming it.
// `simplify` replaces the configured simplification stage when given; `extra_sinks` also receive the
// frames (not owned).
EngineRun RunAndEvaluate(const Config& config, const std::string& dataset, double progress_s,
                         std::unique_ptr<SimplifyStage> simplify = nullptr,
                         const std::vector<PipelineSink*>& extra_sinks = {});

}  // namespace semap::app
