// `semap compare PATH`: every simplification method on the same input, the paper's method plot.
// Mode `incremental` streams a sequence once per method through the engine; mode `single-frame` builds
// one batch map per frame (for the stereo-2015 frames, which have no poses), with depth and labels
// computed once per frame and shared by the methods. Writes compare.md, compare.csv and compare.png
// (mesh size vs RMSE, drawn by gnuplot, with the size of the mesh without ground and wall points as a
// vertical line); in incremental mode also the by-area accuracy against the exact scene mesh (generated
// sequences) and each method's pictures from above (METHOD/top_view*.png).
#include "app/paper/method_comparison.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct CompareArgs {
  CommonArgs common;
  app::CompareRequest request;  // its config_path and overrides come from `common`
};

}  // namespace

void RegisterCompareCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Every simplification method on the same input: markdown table (mesh size, RMSE, completeness, "
      "points kept per class, time) and a PNG plot of mesh size vs RMSE");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->request.path, "dataset folder")->required();
  cmd->add_option("--out", args->request.out, "output folder (compare.md, compare.csv, compare.png)")
      ->capture_default_str();
  cmd->add_option("--mode", args->request.mode,
                  "incremental (stream the sequence per method) | single-frame (one batch map per frame)")
      ->check(CLI::IsMember({"incremental", "single-frame"}))
      ->capture_default_str();
  cmd->add_option("--methods", args->request.methods, "methods to run (default: all), e.g. O PS voxel");
  cmd->add_option("--frames", args->request.frames, "frames to use, 0 = all")
      ->check(FrameCountCheck())
      ->capture_default_str();
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      args->request.config_path = args->common.config_path;
      args->request.overrides = args->common.overrides;
      return app::CompareMethods(args->request) ? kExitOk : kExitFailure;
    });
  });
}

}  // namespace semap::tools
