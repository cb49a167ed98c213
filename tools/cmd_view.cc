// `semap view [RUN_DIR | MESH | --lcm-url URL]`: serves a local web page that shows the map in 3D — a
// finished run folder or mesh file, or a run live from its LCM mesh blocks — until Ctrl-C.
#include <pthread.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "tools/cli_common.h"
#include "tools/view/view_server.h"
#include "tools/view/view_sources.h"

namespace semap::tools {
namespace {

struct ViewArgs {
  CommonArgs common;
  std::string path;
  bool live = false;
  view::ViewServerOptions server;
  view::FinishedViewOptions finished;
  view::LiveViewOptions live_options;
  double seconds = 0.0;  // 0: until Ctrl-C / SIGTERM
};

// Serves until SIGINT / SIGTERM (or `seconds`). The signals are blocked in every thread (civetweb's and the
// LCM thread inherit the mask of the thread that starts them) and taken here with sigtimedwait: no handler,
// no global.
int Serve(const ViewArgs& args) {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  std::unique_ptr<view::ViewModel> model;
  if (args.live) {
    model = view::LiveSource::MakeModel(args.live_options);
  } else {
    model = view::LoadFinished(args.path, args.finished);
  }
  if (args.server.host != "127.0.0.1" && args.server.host != "localhost") {
    spdlog::warn(
        "semap view: listening on {}: the page has no authentication, anyone who can reach this address "
        "sees the map",
        args.server.host);
  }
  // The server before the subscription: a taken port is reported before anything else starts.
  view::ViewServer server(args.server, model.get());
  std::unique_ptr<view::LiveSource> live;
  if (args.live) live = std::make_unique<view::LiveSource>(args.live_options, model.get());
  // The URL on stdout (the command's result), flushed: a script may wait for it.
  std::printf("%s\n", server.url().c_str());
  std::fflush(stdout);
  spdlog::info("semap view: serving {} on {} (Ctrl-C to stop)", args.live ? args.live_options.url : args.path,
               server.url());
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    timespec wait{0, 200'000'000};
    const int sig = sigtimedwait(&stop_signals, nullptr, &wait);
    if (sig == SIGINT || sig == SIGTERM) {
      spdlog::info("semap view: stopped by {}", sig == SIGINT ? "SIGINT" : "SIGTERM");
      break;
    }
    if (args.seconds > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= args.seconds) {
      break;
    }
  }
  return kExitOk;
}

}  // namespace

void RegisterViewCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ViewArgs>();
  auto* cmd = app.add_subcommand(
      "view",
      "Serve a local web page that shows the map in 3D: a finished run folder or mesh file, or a run live "
      "from its LCM mesh blocks (--lcm-url); colours by image colour, semantic label or error, camera "
      "trajectory, frame rate and map size over time");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("SOURCE", args->path,
                  "a `semap run` output folder (mesh.ply, frames.jsonl) or a .ply / .off mesh");
  cmd->add_option("--host", args->server.host, "address to listen on (127.0.0.1: this machine only)")
      ->capture_default_str();
  cmd->add_option("--port", args->server.port, "TCP port; 0 = any free port (the URL is printed)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  auto* url = cmd->add_option("--lcm-url", args->live_options.url,
                              "follow a live `semap run --lcm-url URL` instead of a SOURCE, e.g. "
                              "udpm://239.255.76.67:7667?ttl=0");
  cmd->add_option("--channel-prefix", args->live_options.channel_prefix,
                  "with --lcm-url: the run's channel prefix")
      ->capture_default_str();
  cmd->add_option(
         "--sequence", args->finished.sequence,
         "with a SOURCE: the dataset the run read, for the camera trajectory, the class palette and (a "
         "generated sequence's scene_mesh.ply) the error colouring")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--truth", args->finished.truth,
                  "with a SOURCE: true surface mesh to colour the error against")
      ->check(CLI::ExistingFile);
  cmd->add_option("--up", args->finished.up,
                  "world up axis for the page: auto (the mesh's thinnest axis, y taken as down), z, -y, ...")
      ->check(CLI::IsMember({"auto", "x", "-x", "y", "-y", "z", "-z"}))
      ->capture_default_str();
  cmd->add_option("--seconds", args->seconds, "stop after this long (0: at Ctrl-C or SIGTERM)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e9));
  cmd->callback([=]() {
    args->live = url->count() > 0;
    args->live_options.up = args->finished.up;
    *exit_code = RunGuarded(args->common, [&]() {
      if (args->live == !args->path.empty()) {
        spdlog::error("semap view: give either a SOURCE (run folder or mesh file) or --lcm-url");
        return kExitUsage;
      }
      try {
        return Serve(*args);
      } catch (const view::ViewServerError& e) {
        spdlog::error("semap view: {}", e.what());
        return kExitFailure;
      }
    });
  });
}

}  // namespace semap::tools
