#include "app/run/stream_run.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>

#include "app/eval/eval_report.h"
#include "app/eval/eval_run.h"
#include "app/run/engine_pipeline.h"
#include "app/run/progress_sink.h"
#include "io/atomic_file.h"
#include "io/labels/class_map_yaml.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

// The run's report of its written mesh: the totals printed, eval_frames.csv, eval.json, eval.md and the
// pictures from above in config.output.dir.
MeshEvaluation EvaluateWrittenMesh(const Mesh& mesh, const Config& config, const std::string& dataset) {
  // With semantics.source: enet ENet labels every frame for the static scene (~0.35 s a frame).
  const MeshEvaluation e = EvaluateAsConfigured(mesh, dataset, config);
  PrintEvaluation(e);
  const std::filesystem::path dir(config.output.dir);
  WritePerFrameCsv(e, dir / "eval_frames.csv");
  io::WriteFileAtomically(dir / "eval.json", ToJson(e, /*per_frame=*/false).dump(2) + "\n");
  io::WriteFileAtomically(dir / "eval.md", EvaluationMarkdown(e));
  spdlog::info("wrote {}, {} and {}", (dir / "eval_frames.csv").string(), (dir / "eval.json").string(),
               (dir / "eval.md").string());
  for (const auto& f : WriteTopViews(mesh, e, dir)) spdlog::info("wrote {}", f.string());
  return e;
}

}  // namespace

Config LoadStreamRunConfig(const std::filesystem::path& yaml_path, const std::vector<std::string>& overrides,
                           const std::string& dataset) {
  const Config config = LoadConfig(yaml_path, overrides);
  if (!config.one_frame.one_frame_preset || OpenStreamingSource(config, dataset)->size() != 1) return config;
  spdlog::info(
      "one frame: config/one_frame.yaml's values apply where the config file and --set leave them "
      "(input.one_frame_preset: false keeps the stream defaults)");
  return LoadConfig(yaml_path, overrides, OneFramePresetYaml());
}

StreamRunResult StreamRun(const Config& config, const StreamRunRequest& request) {
  const bool map_node = static_cast<bool>(request.received_frames);
  const RunOdometry odometry = map_node ? RunOdometry{} : PrepareOdometry(config, request.dataset);
  std::unique_ptr<io::FrameSource> source;
  std::int64_t total = 0;  // unknown to a map node
  if (!map_node) {
    source = OpenStreamingSource(config, request.dataset);
    total = source->size();
  }
  spdlog::info("{}: {} frames ({}), method {}, {}, {} depth workers, {}", request.dataset, total,
               map_node ? std::string("depth frames over LCM") : io::DatasetLayoutName(source->layout()),
               SimplifyMethodName(config.simplify.method),
               config.pipeline.mode == PipelineOptions::Mode::kRealtime
                   ? fmt::format("realtime mode at {:g}x the sensor's rate", config.pipeline.realtime_speed)
                   : std::string("exhaustive mode"),
               config.pipeline.depth_workers, request.start_note);

  // Sinks first: an unusable output folder or LCM URL is reported before any work is done.
  RunOutputs outputs(config, request.lcm);
  std::optional<ProgressSink> progress;
  if (request.progress_s) progress.emplace(total, *request.progress_s);
  if (odometry.log) {
    spdlog::info(
        "poses: stereo visual odometry{}",
        odometry.plan.replace_poses ? "" : " beside the sequence's own (the map takes the sequence's)");
    outputs.SetFigureSource([log = odometry.log](std::int64_t id) { return log->Figures(id); });
  }

  std::unique_ptr<SimplifyStage> simplify = request.simplify ? request.simplify() : nullptr;
  const std::unique_ptr<Pipeline> engine =
      map_node
          ? MakeMapNodePipeline(config, request.received_frames(), io::LoadClassMap(config.input.class_map),
                                std::move(simplify))
          : MakeEnginePipeline(config, std::move(source), std::move(simplify), &odometry, request.depth_node);
  Pipeline& pipeline = *engine;
  for (PipelineSink* sink : outputs.sinks()) pipeline.AddSink(sink);
  if (progress) pipeline.AddSink(&*progress);
  for (PipelineSink* sink : request.extra_sinks) pipeline.AddSink(sink);

  StreamRunResult result;
  if (request.on_running) request.on_running(&pipeline);
  result.summary = pipeline.Run();
  if (request.on_running) request.on_running(nullptr);

  const PipelineSummary& summary = result.summary;
  const FrameStats& s = summary.final_stats;
  spdlog::info("{} frames processed, {} dropped, {} failed in {:.2f} s: {:.3f} fps{}", s.frames_processed,
               s.frames_dropped, s.frames_failed, s.elapsed_s, s.fps,
               summary.stopped_early ? " (stopped early)" : "");
  for (const auto& l : s.latencies) {
    spdlog::info("  latency to {:<10} p50 {:8.1f} ms  p95 {:8.1f}  max {:8.1f}", l.name, l.p50_ms, l.p95_ms,
                 l.max_ms);
  }
  for (const auto& st : s.stages) {
    spdlog::info("  {:<13} mean {:8.2f} ms  p50 {:8.2f}  p95 {:8.2f}  max {:8.2f}", st.name, st.mean_ms,
                 st.p50_ms, st.p95_ms, st.max_ms);
  }
  result.mesh = outputs.WrittenMesh();
  const Mesh& mesh = result.mesh;
  spdlog::info("mesh: {} vertices, {} triangles, {:.2f} MB as OFF", mesh.num_vertices(), mesh.num_triangles(),
               static_cast<double>(io::OffSizeBytes(mesh)) / 1e6);
  outputs.LogWritten();
  if (odometry.log) {
    const std::vector<OdometryRecord> records = odometry.log->Records();
    double cpu_ms = 0.0;
    for (const auto& r : records) cpu_ms += r.result.cpu_ms;
    spdlog::info(
        "odometry: {} frames, {} bridged or restarted (tracking failed: not mapped, pose guessed), "
        "mean {:.1f} ms CPU a frame, disparity offset {:+.2f} px {:+.2f} px per row unit at the last frame",
        records.size(), odometry.log->failures(), records.empty() ? 0.0 : cpu_ms / records.size(),
        records.empty() ? 0.0 : records.back().result.disparity_offset.constant_px,
        records.empty() ? 0.0 : records.back().result.disparity_offset.per_row_px);
    try {
      for (const auto& f : WriteOdometryTrajectory(*odometry.log, config.output.dir))
        spdlog::info("wrote {}", f.string());
    } catch (const io::FileError& e) {
      spdlog::error("{}", e.what());
      result.outcome = StreamRunOutcome::kOutputErrors;
      return result;
    }
  }
  if (request.evaluate && mesh.num_triangles() == 0) {
    spdlog::warn("--eval: the mesh has no faces: nothing to evaluate");
  } else if (request.evaluate) {
    // After the run, so that it does not count in the frame rate: every frame's camera against the mesh as
    // written.
    result.evaluation = EvaluateWrittenMesh(mesh, config, request.dataset);
  }
  if (summary.sink_errors > 0) {
    spdlog::error("{} output errors; first: {}", summary.sink_errors, summary.first_sink_error);
    result.outcome = StreamRunOutcome::kOutputErrors;
  } else if (!summary.fatal_error.empty()) {
    spdlog::error("run stopped: {}", summary.fatal_error);
    result.outcome = StreamRunOutcome::kStopped;
  } else if (s.frames_processed == 0 && s.frames_failed > 0) {
    // Not a success with an empty mesh: nothing of the sequence could be used.
    spdlog::error("no frame could be processed: all {} frames failed (see the warnings above{})",
                  s.frames_failed,
                  config.output.frame_stats
                      ? " and " + (std::filesystem::path(config.output.dir) / "errors.jsonl").string()
                      : std::string());
    result.outcome = StreamRunOutcome::kNothingMapped;
  }
  return result;
}

}  // namespace semap::app
