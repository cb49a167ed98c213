// `semap lcm-mesh LOG --out mesh.ply`: rebuild the mesh of a run from an lcm-logger log.
#include <spdlog/spdlog.h>

#include "io/lcm/lcm_log.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterLcmMeshCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string log;
    std::string out;
    std::string channel_prefix = "SEMAP_";
    bool ascii = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("lcm-mesh", "Rebuild the mesh from an lcm-logger log of `semap run` "
                                             "(snapshots + deltas) and write it as PLY or OFF");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("LOG", args->log, "LCM log file written by lcm-logger")->required();
  cmd->add_option("--out", args->out, "output mesh (.ply or .off)")->required();
  cmd->add_option("--channel-prefix", args->channel_prefix, "channel prefix of the run")->capture_default_str();
  cmd->add_flag("--ascii", args->ascii, "write ASCII PLY instead of binary");
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const auto replay = io::ReplayMeshLog(args->log, args->channel_prefix);
      const std::filesystem::path out(args->out);
      if (out.extension() == ".off") {
        io::WriteMeshOff(out, replay.mesh);
      } else {
        io::WriteMeshPly(out, replay.mesh,
                         args->ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);
      }
      spdlog::info("{}: {} snapshots, {} deltas, {} lost messages, last frame {} → {} vertices, {} triangles → {}",
                   args->log, replay.snapshots, replay.deltas, replay.sequence_gaps, replay.last_frame_id,
                   replay.mesh.num_vertices(), replay.mesh.num_triangles(), out.string());
      return replay.sequence_gaps > 0 ? kExitFailure : kExitOk;
    });
  });
}

}  // namespace semap::tools
