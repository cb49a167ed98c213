// `semap run PATH`: stream a sequence through the whole engine (depth → labels → simplification →
// incremental Delaunay map) and write / publish the mesh.
#include <csignal>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "engine/pipeline/pipeline.h"
#include "engine/pipeline/semap_stages.h"
#include "io/atomic_file.h"
#include "app/eval/mesh_evaluation.h"
#include "io/mesh/ply_off.h"
#include "io/output/output_sinks.h"
#include "tools/allocator.h"
#include "tools/cli_common.h"
#include "app/run/engine_run.h"
#include "app/eval/eval_report.h"
#include "app/run/progress_sink.h"

namespace semap::tools {
namespace {

// A signal handler receives no context: this is the one way for SIGINT / SIGTERM to reach the running
// pipeline (the project's one global, lock-free hence async-signal-safe).
std::atomic<Pipeline*> g_running_pipeline{nullptr};

// The first Ctrl-C or SIGTERM (what `timeout`, systemd and container runtimes send) drains the frames in
// flight and writes the mesh so far; a second one ends the process at once (the default actions are back in
// place). SIGPIPE is ignored for the whole process (tools/main.cc).
extern "C" void StopOnSignal(int) {
  if (Pipeline* p = g_running_pipeline.load()) p->RequestStop();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

struct RunArgs {
  CommonArgs common;
  std::string path;
  std::string out;
  std::string method;
  std::string mode;
  std::string lcm_url;
  int frames = -1;
  double progress_s = 1.0;
  bool eval = false;
};

// Command-line shortcuts become config overrides, so that they are validated like any config value.
std::vector<std::string> Overrides(const RunArgs& a) {
  std::vector<std::string> o = a.common.overrides;
  if (!a.out.empty()) o.push_back("output.dir=" + a.out);
  if (!a.method.empty()) o.push_back("simplify.method=" + a.method);
  if (!a.mode.empty()) o.push_back("pipeline.mode=" + a.mode);
  if (a.frames >= 0) o.push_back("input.max_frames=" + std::to_string(a.frames));
  if (!a.lcm_url.empty()) {
    o.push_back("lcm.enabled=true");
    o.push_back("lcm.url=" + a.lcm_url);
  }
  return o;
}

int Run(const RunArgs& args) {
  const app::Config config = app::LoadConfig(args.common.config_path, Overrides(args));
  auto source = app::OpenStreamingSource(config, args.path);
  const std::int64_t total = source->size();
  spdlog::info("{}: {} frames ({}), method {}, {} mode, {} depth workers, {}", args.path, total,
               io::DatasetLayoutName(source->layout()), SimplifyMethodName(config.simplify.method),
               config.pipeline.mode == PipelineOptions::Mode::kRealtime ? "realtime" : "exhaustive",
               config.pipeline.depth_workers, AllocatorDescription());

  // Sinks first: an unusable output folder or LCM URL is reported before any work is done.
  io::MeshFileSink mesh_sink(config.output);
  std::unique_ptr<io::StatsFileSink> stats_sink;
  if (config.output.frame_stats) stats_sink = std::make_unique<io::StatsFileSink>(config.output);
  std::unique_ptr<io::LcmSink> lcm_sink;
  if (config.lcm.enabled) lcm_sink = std::make_unique<io::LcmSink>(std::make_unique<io::LcmPublisher>(config.lcm));
  app::ProgressSink progress(total, args.progress_s);

  const std::unique_ptr<Pipeline> engine = app::MakeEnginePipeline(config, std::move(source));
  Pipeline& pipeline = *engine;
  pipeline.AddSink(&mesh_sink);
  if (stats_sink) pipeline.AddSink(stats_sink.get());
  if (lcm_sink) pipeline.AddSink(lcm_sink.get());
  pipeline.AddSink(&progress);

  g_running_pipeline.store(&pipeline);
  auto previous_int = std::signal(SIGINT, StopOnSignal);
  auto previous_term = std::signal(SIGTERM, StopOnSignal);
  const PipelineSummary summary = pipeline.Run();
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  g_running_pipeline.store(nullptr);

  const FrameStats& s = summary.final_stats;
  spdlog::info("{} frames processed, {} dropped, {} failed in {:.2f} s: {:.3f} fps{}", s.frames_processed,
               s.frames_dropped, s.frames_failed, s.elapsed_s, s.fps, summary.stopped_early ? " (stopped early)" : "");
  for (const auto& st : s.stages) {
    spdlog::info("  {:<13} mean {:8.2f} ms  p50 {:8.2f}  p95 {:8.2f}  max {:8.2f}", st.name, st.mean_ms, st.p50_ms,
                 st.p95_ms, st.max_ms);
  }
  const Mesh mesh = mesh_sink.mesh();
  spdlog::info("mesh: {} vertices, {} triangles, {:.2f} MB as OFF", mesh.num_vertices(), mesh.num_triangles(),
               static_cast<double>(io::OffSizeBytes(mesh)) / 1e6);
  for (const auto& f : mesh_sink.written()) spdlog::info("wrote {}", f.string());
  if (lcm_sink) {
    const auto c = lcm_sink->publisher().counters();
    spdlog::info("LCM: {} mesh messages, {} other, {} send failures, {} dropped", c.mesh_messages,
                 c.other_messages, c.send_failures, c.dropped);
  }
  if (args.eval && mesh.num_triangles() == 0) {
    spdlog::warn("--eval: the mesh has no faces: nothing to evaluate");
  } else if (args.eval) {
    // After the run, so that it does not count in the frame rate: every frame's camera against the final mesh,
    // as written (mesh.ply holds float32 coordinates): `semap eval` of the written mesh gives the same figures.
    Mesh written = mesh;
    for (Eigen::Vector3d& v : written.vertices) v = v.cast<float>().cast<double>();
    const app::MeshEvaluation e = app::EvaluateMesh(written, args.path, config.input, config.eval);
    app::PrintEvaluation(e);
    const std::filesystem::path dir(config.output.dir);
    app::WritePerFrameCsv(e, dir / "eval_frames.csv");
    io::WriteFileAtomically(dir / "eval.json", app::ToJson(e, /*per_frame=*/false).dump(2) + "\n");
    io::WriteFileAtomically(dir / "eval.md", app::EvaluationMarkdown(e));
    spdlog::info("wrote {}, {} and {}", (dir / "eval_frames.csv").string(), (dir / "eval.json").string(),
                 (dir / "eval.md").string());
    for (const auto& f : app::WriteTopViews(mesh, e, dir)) spdlog::info("wrote {}", f.string());
  }
  if (summary.sink_errors > 0) {
    spdlog::error("{} output errors; first: {}", summary.sink_errors, summary.first_sink_error);
    return kExitFailure;
  }
  if (!summary.fatal_error.empty()) {
    spdlog::error("run stopped: {}", summary.fatal_error);
    return kExitFailure;
  }
  if (s.frames_processed == 0 && s.frames_failed > 0) {
    // Not a success with an empty mesh: nothing of the sequence could be used.
    spdlog::error("no frame could be processed: all {} frames failed (see the warnings above{})",
                  s.frames_failed,
                  config.output.frame_stats
                      ? " and " + (std::filesystem::path(config.output.dir) / "errors.jsonl").string()
                      : std::string());
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

void RegisterRunCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Stream a sequence through the engine (SGBM depth → semantic labels → "
                                        "simplification → incremental Delaunay map) and write/publish the mesh");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path, "dataset folder (KITTI raw, odometry or stereo-2015 layout)")->required();
  cmd->add_option("--out", args->out, "output folder (output.dir)");
  cmd->add_option("--method", args->method, "simplification method, e.g. PS or O (simplify.method)");
  cmd->add_option("--mode", args->mode, "exhaustive | realtime (pipeline.mode)");
  cmd->add_option("--frames", args->frames, "frames to process, 0 = all (input.max_frames)")
      ->check(FrameCountCheck());
  cmd->add_option("--lcm-url", args->lcm_url,
                  "publish over LCM at this URL, e.g. udpm://239.255.76.67:7667?ttl=0 (lcm.url)");
  cmd->add_option("--progress-interval", args->progress_s, "seconds between progress lines")->capture_default_str();
  cmd->add_flag("--eval", args->eval,
                "after the run (not counted in the frame rate), evaluate the mesh against every frame's Velodyne "
                "/ exact depth: totals printed, eval_frames.csv, eval.json, eval.md (both protocols; error by class, "
                "distance and triangle size) and top_view*.png (the mesh from above) in the output folder");
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Run(*args); }); });
}

}  // namespace semap::tools
