// `semap eval PATH --mesh MESH.ply`: accuracy of a mesh against the sequence's Velodyne scans (and exact
// depth maps of generated sequences), plus its size; in two protocols (strict and the paper's). With --out, a
// report folder: eval.json, eval.md (both protocols and where the errors come from: by class, reference
// distance and hit-triangle area), per-pixel error images of a few frames and the pictures from above
// (app/eval/eval_run.h does it).
#include "app/eval/eval_run.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterEvalCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    std::string mesh;
    std::string json;
    std::string pictures;
    std::string out;
    int error_images = 3;
    std::vector<std::int64_t> error_frames;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("eval",
                                 "Accuracy of a mesh against the sequence's Velodyne (RMSE, MAE, median, "
                                 "completeness) and exact depth maps when generated; mesh size as OFF");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path, "dataset folder the mesh was built from")->required();
  cmd->add_option("--mesh", args->mesh, "mesh file (.ply or .off)")->required();
  cmd->add_option("--json", args->json, "also write the figures as JSON to this file");
  cmd->add_option("--pictures", args->pictures,
                  "also write the mesh seen from above to this folder: top_view.png, and top_view_error.png "
                  "(coloured by distance to the true surface) for generated sequences");
  auto* out_option = cmd->add_option(
      "--out", args->out,
      "report folder (created): eval.json, eval.md (both protocols; error by class, distance and "
      "triangle size), error_*.png (per-pixel |error| of --error-images frames), top_view*.png");
  cmd->add_option(
         "--error-images", args->error_images,
         "with --out: per-pixel error images of this many frames spread over the sequence (0 = none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str()
      ->needs(out_option);
  cmd->add_option("--error-frames", args->error_frames,
                  "with --out: error images of these frames (ids as on disk) instead of --error-images")
      ->needs(out_option);
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const app::Config config = LoadConfigFrom(args->common);
      app::EvalRequest request{args->path, args->mesh,         args->json,        args->pictures,
                               args->out,  args->error_images, args->error_frames};
      return app::EvaluateMeshFile(config, request) ? kExitOk : kExitFailure;
    });
  });
}

}  // namespace semap::tools
