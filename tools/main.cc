// semap — real-time incremental dense mapping with semantic point-cloud simplification.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <string>

#include "tools/allocator.h"
#include "tools/cli_common.h"

int main(int argc, char** argv) {
  using namespace semap::tools;
  ConfigureAllocator();
  CLI::App app{"semap: dense 3D visual mapping via semantic simplification (stereo KITTI → manifold mesh)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "semap 0.1.0 (" + AllocatorDescription() + ")");
  int exit_code = kExitOk;
  const RegisterFn commands[] = {
      RegisterRunCommand,     RegisterMapSfmCommand,   RegisterConfigCommand,    RegisterSynthCommand,
      RegisterLcmMeshCommand, RegisterSimplifyCommand, RegisterInfoCommand,      RegisterDepthCommand,
      RegisterSegmentCommand, RegisterEvalCommand,     RegisterEvalPosesCommand, RegisterTableCommand,
      RegisterCompareCommand, RegisterRenderCommand,   RegisterViewCommand,      RegisterMapCommand,
  };
  for (auto reg : commands) reg(app, &exit_code);
  // A reader that goes away (`semap run … | head -1`) must not kill a run with SIGPIPE: writes to the closed
  // pipe fail instead (EPIPE), log lines are lost, the run goes on and writes its files.
  std::signal(SIGPIPE, SIG_IGN);
  // The log, warnings and errors go to stderr; stdout carries only what a command prints as its result.
  spdlog::set_default_logger(
      std::make_shared<spdlog::logger>("semap", std::make_shared<spdlog::sinks::stderr_color_sink_mt>()));
  // CLI11 takes an unknown first word for a stray argument ("A subcommand is required"): name it and the
  // valid ones.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    std::string valid;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->check_name(word);
      valid += (valid.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "semap: unknown subcommand '%s'; valid subcommands: %s (semap --help)\n",
                   word.c_str(), valid.c_str());
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  return exit_code;
}
