// `semap lcm-mesh LOG --out mesh.ply` / `semap lcm-mesh --live --url URL --out mesh.ply`: rebuild the mesh
// of a run from its LCM mesh blocks, recorded by lcm-logger or received live.
#include <spdlog/spdlog.h>

#include "app/lcm/replayed_mesh.h"
#include "io/lcm/lcm_log.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterLcmMeshCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string log;
    std::string out;
    std::string channel_prefix = "SEMAP_";
    bool ascii = false;
    bool live = false;
    std::string url = "udpm://239.255.76.67:7667?ttl=0";
    double seconds = 60.0;
    double join_after_s = -1.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("lcm-mesh",
                                 "Rebuild the mesh of `semap run` from its LCM mesh blocks, from an "
                                 "lcm-logger log or live, and write it as PLY or OFF");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("LOG", args->log, "LCM log file written by lcm-logger (not with --live)");
  cmd->add_option("--out", args->out, "output mesh (.ply or .off)")->required();
  cmd->add_option("--channel-prefix", args->channel_prefix, "channel prefix of the run")
      ->capture_default_str();
  cmd->add_flag("--ascii", args->ascii, "write ASCII PLY instead of binary");
  cmd->add_flag("--live", args->live,
                "subscribe instead of reading a log: until the run's last message, "
                "or --seconds");
  cmd->add_option("--url", args->url, "LCM URL to subscribe to with --live")->capture_default_str();
  cmd->add_option("--seconds", args->seconds, "with --live: listen at most this long")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e7));
  cmd->add_option("--join-after", args->join_after_s,
                  "with a LOG: ignore its first S seconds, as a subscriber started late, and report when it "
                  "caught up")
      ->check(CLI::Range(0.0, 1e9));
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      if (args->live == !args->log.empty()) {
        spdlog::error("lcm-mesh: give either a LOG or --live");
        return kExitUsage;
      }
      if (args->live) {
        const auto r = io::ReceiveMeshLive(args->url, args->seconds, args->channel_prefix);
        return app::WriteReplayedMesh(args->url, r, args->out, args->ascii) ? kExitOk : kExitFailure;
      }
      io::MeshReplayOptions options;
      options.channel_prefix = args->channel_prefix;
      options.join_after_s = args->join_after_s;
      return app::WriteReplayedMesh(args->log, io::ReplayMeshLog(args->log, options), args->out, args->ascii)
                 ? kExitOk
                 : kExitFailure;
    });
  });
}

}  // namespace semap::tools
