// `semap lcm-mesh LOG --out mesh.ply` / `semap lcm-mesh --live --url URL --out mesh.ply`: rebuild the mesh
// of a run from its LCM mesh blocks, recorded by lcm-logger or received live.
#include <spdlog/spdlog.h>

#include "io/lcm/lcm_log.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

constexpr size_t kMaxListed = 20;

std::string RunState(const io::MeshReplay& r) {
  if (r.blocks.run_ended) return "run ended";
  if (r.blocks.closing_seen && r.index_complete) return "run closing, every block of its index held";
  return "run not seen to end";
}

int Report(const std::string& source, const io::MeshReplay& r, const std::filesystem::path& out, bool ascii) {
  if (!r.log_problem.empty()) {
    spdlog::warn("{}: {} ({} bytes skipped)", source, r.log_problem, r.damaged_bytes);
  }
  if (r.skipped > 0) {
    spdlog::warn("{}: {} mesh messages skipped as invalid, e.g.:", source, r.skipped);
    for (const auto& why : r.skipped_reasons) spdlog::warn("  {}", why);
  }
  if (r.mesh.num_triangles() == 0) {
    spdlog::error("{}: no triangle rebuilt ({} events, {} mesh messages, {} blocks lacking); nothing written",
                  source, r.events, r.mesh_events, r.missing.size());
    return kExitFailure;
  }
  if (out.extension() == ".off") {
    io::WriteMeshOff(out, r.mesh);
  } else {
    io::WriteMeshPly(out, r.mesh, ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);
  }
  spdlog::info("{}: {} events over {:.1f} s, {} mesh messages ({} bytes, largest event {} bytes), {} duplicates, "
               "{} deltas without their base, {} → {} vertices, {} triangles → {}",
               source, r.events, r.duration_s, r.mesh_events, r.mesh_bytes, r.largest_message, r.blocks.duplicates,
               r.blocks.deltas_without_base, RunState(r), r.mesh.num_vertices(),
               r.mesh.num_triangles(), out.string());
  if (r.converged_after_s >= 0) spdlog::info("late subscriber converged {:.2f} s after joining", r.converged_after_s);
  if (r.blocks.runs > 1) spdlog::warn("{}: {} runs in the log; the mesh is the last run's", source, r.blocks.runs);
  if (r.missing.empty()) return kExitOk;
  spdlog::error("{}: the mesh is incomplete: {} blocks lacking:", source, r.missing.size());
  for (size_t i = 0; i < std::min(kMaxListed, r.missing.size()); ++i) spdlog::error("  {}", r.missing[i]);
  if (r.missing.size() > kMaxListed) spdlog::error("  ... and {} more", r.missing.size() - kMaxListed);
  return kExitFailure;
}

}  // namespace

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
  auto* cmd = app.add_subcommand("lcm-mesh", "Rebuild the mesh of `semap run` from its LCM mesh blocks, from an "
                                             "lcm-logger log or live, and write it as PLY or OFF");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("LOG", args->log, "LCM log file written by lcm-logger (not with --live)");
  cmd->add_option("--out", args->out, "output mesh (.ply or .off)")->required();
  cmd->add_option("--channel-prefix", args->channel_prefix, "channel prefix of the run")->capture_default_str();
  cmd->add_flag("--ascii", args->ascii, "write ASCII PLY instead of binary");
  cmd->add_flag("--live", args->live, "subscribe instead of reading a log: until the run's last message, "
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
        return Report(args->url, r, args->out, args->ascii);
      }
      io::MeshReplayOptions options;
      options.channel_prefix = args->channel_prefix;
      options.join_after_s = args->join_after_s;
      return Report(args->log, io::ReplayMeshLog(args->log, options), args->out, args->ascii);
    });
  });
}

}  // namespace semap::tools
