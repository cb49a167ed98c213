// `semap run PATH`: stream a sequence through the whole engine (depth → labels → simplification →
// incremental Delaunay map) and write / publish the mesh (app/run/stream_run.h does the run).
#include <atomic>
#include <csignal>
#include <optional>
#include <string>

#include "app/run/stream_run.h"
#include "app/split/split_run.h"
#include "engine/pipeline/pipeline.h"
#include "tools/allocator.h"
#include "tools/cli_common.h"

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
  // --realtime [SPEED]: given with no value, the sensor's own rate.
  std::optional<std::string> realtime_speed;
  std::string lcm_url;
  int frames = -1;
  double progress_s = 1.0;
  bool eval = false;
  // A split run's depth node.
  bool publish_depth = false;
  std::string share = "0/1";
  std::string node;
};

// Command-line shortcuts become config overrides, so that they are validated like any config value.
std::vector<std::string> Overrides(const RunArgs& a) {
  using app::Config;
  using app::Override;
  std::vector<std::string> o = a.common.overrides;
  if (!a.out.empty()) o.push_back(Override(&Config::output, &io::OutputOptions::dir, a.out));
  if (!a.method.empty()) o.push_back(Override(&Config::simplify, &SimplifyOptions::method, a.method));
  if (!a.mode.empty()) o.push_back(Override(&Config::pipeline, &PipelineOptions::mode, a.mode));
  if (a.realtime_speed) {
    o.push_back(Override(&Config::pipeline, &PipelineOptions::mode, "realtime"));
    o.push_back(Override(&Config::pipeline, &PipelineOptions::realtime_speed,
                         a.realtime_speed->empty() ? std::string("1") : *a.realtime_speed));
  }
  if (a.frames >= 0)
    o.push_back(Override(&Config::input, &io::FrameSourceOptions::max_frames, std::to_string(a.frames)));
  if (!a.lcm_url.empty()) {
    o.push_back(Override(&Config::lcm, &io::LcmOptions::enabled, "true"));
    o.push_back(Override(&Config::lcm, &io::LcmOptions::url, a.lcm_url));
  }
  return o;
}

// The signal handlers reach the pipeline while it runs; the default actions are back once it has ended.
void StopOnSignals(app::StreamRunRequest* request) {
  using Handler = void (*)(int);
  auto previous = std::make_shared<std::pair<Handler, Handler>>(SIG_DFL, SIG_DFL);
  request->on_running = [previous](Pipeline* pipeline) {
    g_running_pipeline.store(pipeline);
    if (pipeline) {
      previous->first = std::signal(SIGINT, StopOnSignal);
      previous->second = std::signal(SIGTERM, StopOnSignal);
    } else {
      std::signal(SIGINT, previous->first);
      std::signal(SIGTERM, previous->second);
    }
  };
}

int ExitCode(const app::StreamRunResult& result) {
  return result.outcome == app::StreamRunOutcome::kDone ? kExitOk : kExitFailure;
}

int Run(const RunArgs& args) {
  const app::Config config = app::LoadStreamRunConfig(args.common.config_path, Overrides(args), args.path);
  app::StreamRunRequest request;
  request.dataset = args.path;
  request.progress_s = args.progress_s;
  request.evaluate = args.eval;
  request.start_note = AllocatorDescription();
  StopOnSignals(&request);
  if (!args.publish_depth) return ExitCode(app::StreamRun(config, request));
  const app::FrameShare share = app::ParseFrameShare(args.share);
  const std::string node = args.node.empty() ? "depth-" + std::to_string(share.index) : args.node;
  return ExitCode(app::RunDepthNodeOverLcm(config, request, share, node));
}

struct MapArgs {
  CommonArgs common;
  std::string out;
  std::string method;
  std::string lcm_url;
  double progress_s = 1.0;
};

int Map(const MapArgs& args) {
  using app::Config;
  using app::Override;
  std::vector<std::string> o = args.common.overrides;
  if (!args.out.empty()) o.push_back(Override(&Config::output, &io::OutputOptions::dir, args.out));
  if (!args.method.empty()) o.push_back(Override(&Config::simplify, &SimplifyOptions::method, args.method));
  if (!args.lcm_url.empty()) o.push_back(Override(&Config::lcm, &io::LcmOptions::url, args.lcm_url));
  const app::Config config = app::LoadConfig(args.common.config_path, o);
  app::StreamRunRequest request;
  request.dataset = "map node";
  request.progress_s = args.progress_s;
  request.start_note = AllocatorDescription();
  StopOnSignals(&request);
  return ExitCode(app::RunMapNodeOverLcm(config, request));
}

}  // namespace

void RegisterRunCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run",
                                 "Stream a sequence through the engine (SGBM depth → semantic labels → "
                                 "simplification → incremental Delaunay map) and write/publish the mesh");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path,
                  "dataset folder (KITTI raw, odometry, stereo-2015 or Strecha multi-view layout)")
      ->required();
  cmd->add_option("--out", args->out, "output folder (output.dir)");
  cmd->add_option("--method", args->method, "simplification method, e.g. PS or O (simplify.method)");
  cmd->add_option("--mode", args->mode, "exhaustive | realtime (pipeline.mode)");
  cmd->add_option(
         "--realtime", args->realtime_speed,
         "play the frames at their time stamps, SPEED times the sensor's rate (1 when no SPEED is given), "
         "as a camera delivers them: the engine drops the oldest waiting frame when it falls behind "
         "(pipeline.mode=realtime, pipeline.realtime_speed)")
      ->expected(0, 1)
      ->type_name("[SPEED]");
  cmd->add_option("--frames", args->frames, "frames to process, 0 = all (input.max_frames)")
      ->check(FrameCountCheck());
  cmd->add_option("--lcm-url", args->lcm_url,
                  "publish over LCM at this URL, e.g. udpm://239.255.76.67:7667?ttl=0 (lcm.url)");
  cmd->add_option("--progress-interval", args->progress_s, "seconds between progress lines")
      ->capture_default_str();
  cmd->add_flag(
      "--eval", args->eval,
      "after the run (not counted in the frame rate), evaluate the mesh against every frame's Velodyne "
      "/ exact depth: totals printed, eval_frames.csv, eval.json, eval.md (both protocols; error by class, "
      "distance and triangle size) and top_view*.png (the mesh from above) in the output folder");
  cmd->add_flag("--publish-depth", args->publish_depth,
                "a split run's depth node: compute the frames' depth and labels and publish them over LCM "
                "(lcm.url, channel <lcm.channel_prefix>DEPTH_FRAME, run split.run_id) for `semap map`; no "
                "map and no mesh files here");
  cmd->add_option("--share", args->share,
                  "with --publish-depth: compute frames I, I+N, I+2N, ... of the sequence (I/N, e.g. 0/2)")
      ->capture_default_str();
  cmd->add_option("--node", args->node,
                  "with --publish-depth: this depth node's name in the map node's messages (default "
                  "depth-I)");
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Run(*args); }); });
}

void RegisterMapCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<MapArgs>();
  auto* cmd = app.add_subcommand(
      "map",
      "A split run's map node: build the map from the depth frames that `semap run --publish-depth` nodes "
      "publish over LCM, and write/publish the mesh as `semap run` does");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("--out", args->out, "output folder (output.dir)");
  cmd->add_option("--method", args->method, "simplification method, e.g. PS or O (simplify.method)");
  cmd->add_option("--lcm-url", args->lcm_url,
                  "receive depth frames (and publish the mesh, with lcm.enabled) at this URL (lcm.url)");
  cmd->add_option("--progress-interval", args->progress_s, "seconds between progress lines")
      ->capture_default_str();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Map(*args); }); });
}

}  // namespace semap::tools
