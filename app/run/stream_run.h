// A run of the engine on one sequence: `semap run`'s, and each run of `semap table` and `semap compare`. The
// sequence streams through the whole engine into the configured outputs (mesh files, stats, LCM, progress);
// optionally the mesh as written (mesh.ply read back) is then evaluated as `semap eval` evaluates it, so that
// every figure reported for a run is `semap eval`'s of its mesh.ply.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "app/eval/mesh_evaluation.h"
#include "app/run/engine_pipeline.h"
#include "app/run/run_outputs.h"
#include "engine/core/mesh.h"
#include "engine/pipeline/pipeline.h"
#include "engine/pipeline/stages.h"

namespace semap::app {

struct StreamRunRequest {
  std::string dataset;  // the sequence's folder (KITTI raw, odometry or stereo-2015 layout)
  // Seconds between progress lines (0: a line every frame); no progress line when unset.
  std::optional<double> progress_s = 1.0;
  // After the run (not counted in its frame rate): the written mesh against every frame's Velodyne / exact
  // depth, as `semap eval` measures it; the totals printed, eval_frames.csv, eval.json, eval.md and
  // top_view*.png in config.output.dir.
  bool evaluate = false;
  // kOff: no LCM whatever lcm.enabled says.
  RunOutputs::Lcm lcm = RunOutputs::Lcm::kAsConfigured;
  // When set, makes the simplification stage instead of the configured windowed one.
  std::function<std::unique_ptr<SimplifyStage>()> simplify;
  // Also receive every frame, after the outputs and the progress line (not owned).
  std::vector<PipelineSink*> extra_sinks;
  // Told the running pipeline once it starts, and nullptr once it has finished: how a caller stops it from
  // elsewhere (Pipeline::RequestStop is thread-safe), e.g. from a signal handler.
  std::function<void(Pipeline*)> on_running;
  // Appended to the start line (e.g. which allocator serves the process).
  std::string start_note;
  // A split run's depth node (not owned): only its share of the frames, each frame's depth and labels to its
  // sink; no map (the mesh files are empty; frames.csv and summary.json account for the frames).
  const DepthNodeWiring* depth_node = nullptr;
  // A split run's map node: the frames, with their depth, from here instead of `dataset`'s images (`dataset`
  // then only names the run); labels in the scheme of input.class_map.
  std::function<std::unique_ptr<FrameReader>()> received_frames;
};

// How a run ended, for the exit status.
enum class StreamRunOutcome {
  kDone,           // every frame went through (or the run was asked to stop): outputs complete
  kOutputErrors,   // a sink failed (e.g. the disk filled up): its first error was logged
  kStopped,        // a fatal stage error stopped the run (logged); what was mapped so far is written
  kNothingMapped,  // every frame failed: no map at all (the warnings and errors.jsonl say why)
};

struct StreamRunResult {
  StreamRunOutcome outcome = StreamRunOutcome::kDone;
  PipelineSummary summary;  // frame rate (frames / seconds of the whole incremental build), stage times
  Mesh mesh;                // the mesh as written (RunOutputs::WrittenMesh)
  // With StreamRunRequest::evaluate, `mesh` against the sequence; unset when it has no faces (logged), or
  // when writing the odometry's trajectory failed (kOutputErrors) and the run ended there.
  std::optional<MeshEvaluation> evaluation;
};

// The config of `semap run DATASET`: LoadConfig(yaml_path, overrides), and, for a run of exactly one frame
// (the sequence, or input.first_frame / input.max_frames, selects one) with input.one_frame_preset on, the
// same with OneFramePresetYaml() under the file and the overrides (logged). Throws what LoadConfig and
// opening the sequence throw.
Config LoadStreamRunConfig(const std::filesystem::path& yaml_path, const std::vector<std::string>& overrides,
                           const std::string& dataset);

// Opens the sequence and the sinks (an unusable output folder or LCM URL throws before any work is done),
// runs the pipeline, logs the run's figures and what it wrote, and evaluates the written mesh when asked.
// How the run ended is the result's outcome (logged when not kDone); what throws is what keeps the run from
// starting or its mesh from being measured: opening the sequence or a sink, reading mesh.ply back, the
// evaluation.
StreamRunResult StreamRun(const Config& config, const StreamRunRequest& request);

}  // namespace semap::app
