// semap — real-time incremental dense mapping with semantic point-cloud simplification.
#include <CLI/CLI.hpp>

#include "tools/allocator.h"
#include "tools/cli_common.h"

int main(int argc, char** argv) {
  using namespace semap::tools;
  CLI::App app{"semap: dense 3D visual mapping via semantic simplification (stereo KITTI → manifold mesh)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "semap 0.1.0 (" + AllocatorDescription() + ")");
  int exit_code = kExitOk;
  const RegisterFn commands[] = {
      RegisterRunCommand,
      RegisterMapSfmCommand,
      RegisterConfigCommand,
      RegisterSynthCommand,
      RegisterLcmMeshCommand,
      RegisterSimplifyCommand,
      RegisterInfoCommand,
      RegisterDepthCommand,
      RegisterSegmentCommand,
      RegisterEvalCommand,
      RegisterTableCommand,
      RegisterCompareCommand,
      RegisterRenderCommand,
  };
  for (auto reg : commands) reg(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  return exit_code;
}
