#include "tools/eval_report.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "io/atomic_file.h"

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

nlohmann::json ToJson(const io::MeshEvaluation& e, bool per_frame) {
  nlohmann::json j{{"vertices", e.vertices}, {"triangles", e.triangles}, {"off_bytes", e.off_bytes},
                   {"frames", e.frames}, {"frames_unreadable", e.frames_unreadable}};
  if (e.frames_with_lidar > 0) j["lidar"] = ToJson(e.lidar);
  if (e.exact_depth) j["exact_depth"] = ToJson(*e.exact_depth);
  if (e.scene) {
    j["scene_mesh"] = {{"threshold_m", e.scene_threshold_m},
                       {"accuracy", e.scene->accuracy},
                       {"mean_accuracy_m", e.scene->mean_accuracy_m},
                       {"completeness", e.scene->completeness},
                       {"mean_completeness_m", e.scene->mean_completeness_m},
                       {"reconstruction_samples", e.scene->reconstruction_samples},
                       {"truth_samples", e.scene->truth_samples}};
  }
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
    std::printf("vs scene mesh accuracy %.1f %% (mean %.4f m), completeness %.1f %% (mean %.4f m) at tau = %.2f m\n",
                100.0 * e.scene->accuracy, e.scene->mean_accuracy_m, 100.0 * e.scene->completeness,
                e.scene->mean_completeness_m, e.scene_threshold_m);
  }
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
