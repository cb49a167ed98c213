// What every subcommand shares: the config options, logging and the mapping of errors to exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "app/config/config.h"

namespace semap::tools {

// Exit codes of the `semap` executable.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // the job ran and failed (bad data, I/O error)
inline constexpr int kExitUsage = 2;    // bad command line or config

// Options every subcommand accepts.
struct CommonArgs {
  std::string config_path;             // --config FILE
  std::vector<std::string> overrides;  // --set section.key=value (repeatable)
  std::string log_level = "info";      // --log-level
};

// Adds --config, --set and --log-level to a subcommand.
void AddCommonOptions(CLI::App* cmd, CommonArgs* args);

// Check of a --frames option: a whole number >= 0 (0 = all frames); "-5" is refused, not taken for "all".
CLI::Validator FrameCountCheck();

// Loads the config from the common args (throws app::ConfigError).
app::Config LoadConfigFrom(const CommonArgs& args);

// Runs a subcommand body, turning exceptions into a clear message on stderr and an exit code.
int RunGuarded(const CommonArgs& args, const std::function<int()>& body);

// Each subcommand registers itself on the root app; `exit_code` receives the command's result.
using RegisterFn = void (*)(CLI::App& app, int* exit_code);
void RegisterConfigCommand(CLI::App& app, int* exit_code);
void RegisterSynthCommand(CLI::App& app, int* exit_code);
void RegisterLcmMeshCommand(CLI::App& app, int* exit_code);
void RegisterSimplifyCommand(CLI::App& app, int* exit_code);
void RegisterInfoCommand(CLI::App& app, int* exit_code);
void RegisterDepthCommand(CLI::App& app, int* exit_code);
void RegisterSegmentCommand(CLI::App& app, int* exit_code);
void RegisterEvalCommand(CLI::App& app, int* exit_code);
void RegisterEvalPosesCommand(CLI::App& app, int* exit_code);
void RegisterRunCommand(CLI::App& app, int* exit_code);
void RegisterMapCommand(CLI::App& app, int* exit_code);
void RegisterTableCommand(CLI::App& app, int* exit_code);
void RegisterCompareCommand(CLI::App& app, int* exit_code);
void RegisterRenderCommand(CLI::App& app, int* exit_code);
void RegisterMapSfmCommand(CLI::App& app, int* exit_code);
void RegisterViewCommand(CLI::App& app, int* exit_code);

}  // namespace semap::tools
