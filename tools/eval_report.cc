#include "tools/eval_report.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "engine/eval/top_view.h"
#include "io/atomic_file.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"

namespace semap::tools {
namespace {

void Print(const char* what, const DepthAccuracy& a) {
  std::printf("%-13s RMSE %.4f m  MAE %.4f m  median %.4f m  bias %+.4f m  completeness %.1f %% (%lld of %lld px)\n",
              what, a.rmse_m, a.mae_m, a.median_abs_m, a.mean_error_m, 100.0 * a.completeness,
              static_cast<long long>(a.compared_pixels), static_cast<long long>(a.reference_pixels));
}

void CsvFields(std::ostream& out, const std::optional<DepthAccuracy>& a) {
  if (!a) {
    out << ",,,,";
    return;
  }
  out << ',' << a->rmse_m << ',' << a->mae_m << ',' << a->median_abs_m << ',' << a->mean_error_m << ','
      << a->completeness;
}

}  // namespace

nlohmann::json ToJson(const DepthAccuracy& a) {
  return {{"rmse_m", a.rmse_m},           {"mae_m", a.mae_m},
          {"median_abs_m", a.median_abs_m}, {"mean_error_m", a.mean_error_m},
          {"completeness", a.completeness}, {"reference_pixels", a.reference_pixels},
          {"compared_pixels", a.compared_pixels}};
}

nlohmann::json ToJson(const SurfaceMetrics& s) {
  return {{"threshold_m", s.threshold_m},
          {"near_m", s.near_m},
          {"far_m", s.far_m},
          {"area_m2", s.area_m2},
          {"accuracy", s.accuracy},
          {"area_within_near", s.area_within_near},
          {"area_beyond_near", s.area_beyond_near},
          {"area_beyond_far", s.area_beyond_far},
          {"mean_distance_m", s.mean_distance_m},
          {"area_samples", s.area_samples},
          {"vertex_accuracy", s.vertex_accuracy},
          {"vertex_mean_distance_m", s.vertex_mean_distance_m},
          {"vertex_samples", s.vertex_samples},
          {"completeness", s.completeness},
          {"mean_completeness_m", s.mean_completeness_m},
          {"truth_samples", s.truth_samples}};
}

nlohmann::json ToJson(const io::MeshEvaluation& e, bool per_frame) {
  nlohmann::json j{{"vertices", e.vertices}, {"triangles", e.triangles}, {"off_bytes", e.off_bytes},
                   {"frames", e.frames}, {"frames_unreadable", e.frames_unreadable}};
  if (e.frames_with_lidar > 0) j["lidar"] = ToJson(e.lidar);
  if (e.exact_depth) j["exact_depth"] = ToJson(*e.exact_depth);
  if (e.scene) j["scene_mesh"] = ToJson(*e.scene);
  if (per_frame) {
    j["per_frame"] = nlohmann::json::array();
    for (const io::FrameAccuracy& f : e.per_frame) {
      nlohmann::json fj{{"frame_id", f.frame_id}};
      if (f.lidar) fj["lidar"] = ToJson(*f.lidar);
      if (f.exact_depth) fj["exact_depth"] = ToJson(*f.exact_depth);
      j["per_frame"].push_back(fj);
    }
  }
  return j;
}

void PrintEvaluation(const io::MeshEvaluation& e) {
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
  if (e.scene) {
    const SurfaceMetrics& s = *e.scene;
    std::printf("vs scene mesh accuracy %.1f %% of the area within tau = %.2f m (%.1f %% within %.2f m, %.1f %% beyond "
                "%.2f m, %.1f %% beyond %.2f m, mean %.3f m; area %.0f m2, %lld samples)\n",
                100.0 * s.accuracy, s.threshold_m, 100.0 * s.area_within_near, s.near_m, 100.0 * s.area_beyond_near,
                s.near_m, 100.0 * s.area_beyond_far, s.far_m, s.mean_distance_m, s.area_m2,
                static_cast<long long>(s.area_samples));
    std::printf("              per vertex and centroid (every triangle once, whatever its size) %.1f %% within tau "
                "(mean %.3f m)\n",
                100.0 * s.vertex_accuracy, s.vertex_mean_distance_m);
    std::printf("              completeness %.1f %% (mean %.4f m) at tau = %.2f m\n", 100.0 * s.completeness,
                s.mean_completeness_m, s.threshold_m);
  }
}

std::vector<std::filesystem::path> WriteTopViews(const Mesh& mesh, const io::MeshEvaluation& e,
                                                 const std::filesystem::path& dir) {
  const Eigen::Vector3d up = e.camera_up.norm() > 0.0 ? e.camera_up : Eigen::Vector3d::UnitZ();
  std::vector<std::filesystem::path> written;
  TopViewOptions options;
  io::WritePng(dir / "top_view.png", RenderTopView(mesh, up, options, {}, e.camera_centers).image);
  written.push_back(dir / "top_view.png");
  if (e.scene && !e.scene_mesh_path.empty()) {
    const SurfaceDistance to_truth(io::ReadMeshPly(e.scene_mesh_path));
    options.colour = TopViewColour::kError;
    options.error_bins_m = {e.scene->threshold_m, e.scene->near_m, e.scene->far_m};
    const auto distance = [&](const Eigen::Vector3d& p) { return to_truth(p); };
    io::WritePng(dir / "top_view_error.png", RenderTopView(mesh, up, options, distance, e.camera_centers).image);
    written.push_back(dir / "top_view_error.png");
  }
  return written;
}

void WritePerFrameCsv(const io::MeshEvaluation& e, const std::filesystem::path& path) {
  io::AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "frame_id,lidar_rmse_m,lidar_mae_m,lidar_median_m,lidar_bias_m,lidar_completeness,"
         "exact_rmse_m,exact_mae_m,exact_median_m,exact_bias_m,exact_completeness\n";
  for (const io::FrameAccuracy& f : e.per_frame) {
    out << f.frame_id;
    CsvFields(out, f.lidar);
    CsvFields(out, f.exact_depth);
    out << '\n';
  }
  file.Commit();
}

}  // namespace semap::tools
