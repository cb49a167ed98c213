// `semap eval PATH --mesh MESH.ply`: accuracy of a mesh against the sequence's Velodyne scans (and exact
// depth maps of generated sequences), plus its size.
#include <fstream>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "io/eval/mesh_evaluation.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

nlohmann::json ToJson(const DepthAccuracy& a) {
  return {{"rmse_m", a.rmse_m},           {"mae_m", a.mae_m},
          {"median_abs_m", a.median_abs_m}, {"mean_error_m", a.mean_error_m},
          {"completeness", a.completeness}, {"reference_pixels", a.reference_pixels},
          {"compared_pixels", a.compared_pixels}};
}

void Print(const char* what, const DepthAccuracy& a) {
  std::printf("%-13s RMSE %.4f m  MAE %.4f m  median %.4f m  bias %+.4f m  completeness %.1f %% (%lld of %lld px)\n",
              what, a.rmse_m, a.mae_m, a.median_abs_m, a.mean_error_m, 100.0 * a.completeness,
              static_cast<long long>(a.compared_pixels), static_cast<long long>(a.reference_pixels));
}

}  // namespace

void RegisterEvalCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    std::string mesh;
    std::string json;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("eval", "Accuracy of a mesh against the sequence's Velodyne (RMSE, MAE, median, "
                                         "completeness) and exact depth maps when generated; mesh size as OFF");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path, "dataset folder the mesh was built from")->required();
  cmd->add_option("--mesh", args->mesh, "mesh file (.ply or .off)")->required();
  cmd->add_option("--json", args->json, "also write the figures as JSON to this file");
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const io::Config config = LoadConfigFrom(args->common);
      const std::filesystem::path mesh_path(args->mesh);
      const Mesh mesh = mesh_path.extension() == ".off" ? io::ReadMeshOff(mesh_path) : io::ReadMeshPly(mesh_path);
      const auto e = io::EvaluateMesh(mesh, args->path, config.input, config.eval);
      std::printf("mesh          %zu vertices, %zu triangles, %.3f MB as OFF\n", e.vertices, e.triangles,
                  static_cast<double>(e.off_bytes) / 1e6);
      std::printf("frames        %lld evaluated (%lld with Velodyne, %lld with exact depth)\n",
                  static_cast<long long>(e.frames), static_cast<long long>(e.frames_with_lidar),
                  static_cast<long long>(e.frames_with_exact_depth));
      if (e.frames_unreadable > 0) {
        spdlog::warn("{} frame(s) could not be read and were not evaluated; first: {}", e.frames_unreadable,
                     e.first_unreadable);
      }
      if (e.frames_with_lidar > 0) Print("vs Velodyne", e.lidar);
      if (e.exact_depth) Print("vs exact depth", *e.exact_depth);
      if (!args->json.empty()) {
        nlohmann::json j{{"mesh", args->mesh}, {"vertices", e.vertices}, {"triangles", e.triangles},
                         {"off_bytes", e.off_bytes}, {"frames", e.frames},
                         {"frames_unreadable", e.frames_unreadable}};
        if (e.frames_with_lidar > 0) j["lidar"] = ToJson(e.lidar);
        if (e.exact_depth) j["exact_depth"] = ToJson(*e.exact_depth);
        std::ofstream(args->json) << j.dump(2) << "\n";
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
