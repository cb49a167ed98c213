// `semap run`: one sequence streamed through the whole engine into the configured outputs (mesh files, stats,
// LCM, progress), and optionally evaluated afterwards.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "engine/pipeline/pipeline.h"

namespace semap::app {

struct StreamRunRequest {
  std::string dataset;      // the sequence's folder (KITTI raw, odometry or stereo-2015 layout)
  double progress_s = 1.0;  // seconds between progress lines (0 = none)
  // After the run (not counted in its frame rate): the written mesh against every frame's Velodyne / exact
  // depth, with eval_frames.csv, eval.json, eval.md and top_view*.png in config.output.dir.
  bool evaluate = false;
  // Told the running pipeline once it starts, and nullptr once it has finished: how a caller stops it from
  // elsewhere (Pipeline::RequestStop is thread-safe), e.g. from a signal handler.
  std::function<void(Pipeline*)> on_running;
  // Appended to the start line (e.g. which allocator serves the process).
  std::string start_note;
};

// How a run ended, for the exit status.
enum class StreamRunOutcome {
  kDone,           // every frame went through (or the run was asked to stop): outputs complete
  kOutputErrors,   // a sink failed (e.g. the disk filled up): its first error was logged
  kStopped,        // a fatal stage error stopped the run (logged); what was mapped so far is written
  kNothingMapped,  // every frame failed: no map at all (the warnings and errors.jsonl say why)
};

// The config of `semap run DATASET`: LoadConfig(yaml_path, overrides), and, for a run of exactly one frame
// (the sequence, or input.first_frame / input.max_frames, selects one) with input.one_frame_preset on, the
// same with OneFramePresetYaml() under the file and the overrides (logged). Throws what LoadConfig and
// opening the sequence throw.
Config LoadStreamRunConfig(const std::filesystem::path& yaml_path, const std::vector<std::string>& overrides,
                           const std::string& dataset);

// Opens the sequence and the sinks (an unusable output folder or LCM URL throws before any work is done),
// runs the pipeline, logs the run's figures and what it wrote. Throws what opening the sequence or a sink,
// or the evaluation, throws.
StreamRunOutcome StreamRun(const Config& config, const StreamRunRequest& request);

}  // namespace semap::app
