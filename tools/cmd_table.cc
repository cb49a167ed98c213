// `semap table PATH...`: the paper's incremental table. Each sequence is streamed twice through the
// engine (exhaustive mode), Original (O) and Incremental Simplification (PS); the table gives accuracy
// against Velodyne (RMSE, the paper's figure), frame rate, completeness, mesh size and the speed-up, with
// the paper's own figures beside them, in two protocols side by side (strict: every error in the configured
// depth range; paper: reference depth <= 15 m, |error| <= 2 m, as the authors' evaluator), and for generated
// sequences the by-area accuracy against the exact scene mesh; each run's folder gets its pictures from above
// (top_view*.png).
#include "app/paper/incremental_table.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct TableArgs {
  CommonArgs common;
  app::TableRequest request;  // its config_path and overrides come from `common`
};

}  // namespace

void RegisterTableCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<TableArgs>();
  auto* cmd = app.add_subcommand(
      "table",
      "The paper's incremental table: stream each sequence with O and with PS, report RMSE vs Velodyne, "
      "f/s, completeness, mesh size and speed-up beside the paper's figures");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->request.datasets,
                  "sequences (KITTI raw or odometry layout), each PATH or NAME=PATH")
      ->required();
  cmd->add_option("--out", args->request.out, "folder for the runs, table.md and table.json")
      ->capture_default_str();
  cmd->add_option("--frames", args->request.frames, "frames per sequence, 0 = all")
      ->check(FrameCountCheck())
      ->capture_default_str();
  cmd->add_option("--progress-interval", args->request.progress_s, "seconds between progress lines, 0 = none")
      ->capture_default_str();
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      args->request.config_path = args->common.config_path;
      args->request.overrides = args->common.overrides;
      return app::WriteIncrementalTable(args->request) ? kExitOk : kExitFailure;
    });
  });
}

}  // namespace semap::tools
