// `semap eval PATH --mesh MESH.ply`: accuracy of a mesh against the sequence's Velodyne scans (and exact
// depth maps of generated sequences), plus its size; in two protocols (strict and the paper's). With --out, a
// report folder: eval.json, eval.md (both protocols and where the errors come from: by class, reference
// distance and hit-triangle area), per-pixel error images of a few frames and the pictures from above.
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "io/atomic_file.h"
#include "app/eval/mesh_evaluation.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"
#include "app/eval/eval_report.h"

namespace semap::tools {
namespace {

}  // namespace

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
  auto* cmd = app.add_subcommand("eval", "Accuracy of a mesh against the sequence's Velodyne (RMSE, MAE, median, "
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
      const std::filesystem::path mesh_path(args->mesh);
      const Mesh mesh = mesh_path.extension() == ".off" ? io::ReadMeshOff(mesh_path) : io::ReadMeshPly(mesh_path);
      // A mesh without faces has no surface to measure: an RMSE of 0 would read as perfect.
      if (mesh.num_triangles() == 0) throw io::FileError(mesh_path, "mesh has no faces: nothing to evaluate");
      app::MeshEvaluationOptions options;
      if (!args->out.empty()) {
        options.error_images = args->error_images;
        options.error_image_frames = args->error_frames;
      }
      const auto e = app::EvaluateMesh(mesh, args->path, config.input, config.eval, options);
      app::PrintEvaluation(e);
      if (!args->json.empty()) {
        nlohmann::json j = app::ToJson(e, /*per_frame=*/true);
        j["mesh"] = args->mesh;
        io::WriteFileAtomically(args->json, j.dump(2) + "\n");
      }
      if (!args->pictures.empty()) {
        std::filesystem::create_directories(args->pictures);
        for (const auto& f : app::WriteTopViews(mesh, e, args->pictures)) spdlog::info("wrote {}", f.string());
      }
      if (!args->out.empty()) {
        const std::filesystem::path out(args->out);
        std::filesystem::create_directories(out);
        nlohmann::json j = app::ToJson(e, /*per_frame=*/true);
        j["mesh"] = args->mesh;
        io::WriteFileAtomically(out / "eval.json", j.dump(2) + "\n");
        io::WriteFileAtomically(out / "eval.md", app::EvaluationMarkdown(e));
        std::vector<std::filesystem::path> written = app::WriteErrorImages(e, out);
        for (const auto& f : app::WriteTopViews(mesh, e, out)) written.push_back(f);
        spdlog::info("wrote {} and {} ({} pictures)", (out / "eval.json").string(),
                     (out / "eval.md").string(), written.size());
        if (!args->error_frames.empty() && e.error_images.empty()) {
          spdlog::warn(
              "--error-frames: none of the named frames was evaluated (ids as on disk, with a pose)");
        }
      }
      if (e.frames_with_lidar == 0 && !e.exact_depth) {
        spdlog::error("{}: no frame with a pose and Velodyne or exact depth to compare with", args->path);
        return kExitFailure;
      }
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
