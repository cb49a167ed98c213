#include "app/eval/eval_report.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "engine/eval/top_view.h"
#include "io/atomic_file.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

// One protocol's line: its figures and filters (ProtocolFilters, then `filters_suffix`).
void Print(const char* what, const DepthAccuracy& a, const char* protocol,
           const DepthAccuracyOptions& filters, const std::string& filters_suffix = "") {
  std::printf(
      "%-13s RMSE %.4f m  MAE %.4f m  median %.4f m  bias %+.4f m  completeness %.1f %% (%lld of %lld px)"
      "  [%s: %s",
      what, a.rmse_m, a.mae_m, a.median_abs_m, a.mean_error_m, 100.0 * a.completeness,
      static_cast<long long>(a.compared_pixels), static_cast<long long>(a.reference_pixels), protocol,
      (ProtocolFilters(filters) + filters_suffix).c_str());
  if (filters.max_abs_error_m > 0.0) {
    std::printf("; %lld px beyond left out", static_cast<long long>(a.excluded_pixels));
  }
  std::printf("]\n");
}

std::string Fixed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

// One protocol's row of the summary table (filters as Print's).
std::string ProtocolRow(const char* protocol, const char* reference, const DepthAccuracy& a,
                        const DepthAccuracyOptions& filters, const std::string& filters_suffix = "") {
  return std::string("| ") + protocol + " | " + reference + " | " + ProtocolFilters(filters) +
         filters_suffix + " | " + Fixed("%.4f", a.rmse_m) + " | " + Fixed("%.4f", a.mae_m) + " | " +
         Fixed("%.4f", a.median_abs_m) + " | " + Fixed("%+.4f", a.mean_error_m) + " | " +
         Fixed("%.1f %%", 100.0 * a.completeness) + " | " +
         std::to_string(a.compared_pixels - a.excluded_pixels) + " | " + std::to_string(a.excluded_pixels) +
         " |\n";
}

// What the static protocol adds to the strict filters: the pixels of movable classes left out.
std::string StaticSuffix(const MeshEvaluation& e) {
  return ", movable classes left out (the frames' own labels, " + std::to_string(e.frames_with_labels) +
         " frames)";
}

std::string BinsMarkdown(const char* what, const std::vector<ErrorBin>& bins, bool completeness,
                         double large_m) {
  char header[160];
  std::snprintf(header, sizeof(header),
                "| %s | pixels compared | RMSE (m) | median abs (m) | mean (m) | > %g m |%s\n", what, large_m,
                completeness ? " completeness |" : "");
  std::string md = header;
  md += completeness ? "|---|---|---|---|---|---|---|\n" : "|---|---|---|---|---|---|\n";
  for (const ErrorBin& b : bins) {
    const bool any = b.compared_pixels > 0;
    const auto cell = [&md](bool defined, const char* format, double value) {
      md.append(" ").append(defined ? Fixed(format, value) : std::string("–")).append(" |");
    };
    md.append("| ").append(b.name).append(" | ").append(std::to_string(b.compared_pixels)).append(" |");
    cell(any, "%.3f", b.rmse_m);
    cell(any, "%.3f", b.median_abs_m);
    cell(any, "%+.3f", b.mean_error_m);
    cell(any, "%.1f %%", 100.0 * b.share_large);
    if (completeness) cell(b.reference_pixels > 0, "%.1f %%", 100.0 * b.completeness);
    md.append("\n");
  }
  return md;
}

std::string BreakdownMarkdown(const char* reference, const ErrorBreakdown& b,
                              const std::string& class_source) {
  std::string md = std::string("\n### Against ") + reference + "\n\n";
  md += "By class of the pixel (classes from: " + class_source + ")";
  if (class_source.find("mesh labels") != std::string::npos) {
    md += " (with mesh labels a hole has no triangle: its pixels are \"no class\")";
  }
  md += ":\n\n";
  md += BinsMarkdown("class", b.by_class, true, b.large_error_m);
  md += "\nBy reference distance (camera-frame z of the reference):\n\n";
  md += BinsMarkdown("distance", b.by_distance, true, b.large_error_m);
  md += "\nBy area of the mesh triangle the pixel's ray hits first (holes have no triangle):\n\n";
  md += BinsMarkdown("triangle area", b.by_triangle_area, false, b.large_error_m);
  return md;
}

nlohmann::json BinsJson(const std::vector<ErrorBin>& bins) {
  nlohmann::json j = nlohmann::json::array();
  for (const ErrorBin& b : bins) {
    nlohmann::json bj{{"name", b.name},
                      {"reference_pixels", b.reference_pixels},
                      {"compared_pixels", b.compared_pixels},
                      {"completeness", b.completeness},
                      {"rmse_m", b.rmse_m},
                      {"median_abs_m", b.median_abs_m},
                      {"mean_error_m", b.mean_error_m},
                      {"share_large", b.share_large},
                      {"large_pixels", b.large_pixels}};
    if (b.label >= 0) bj["label"] = b.label;
    if (b.label < 0 && b.name != "no class") {
      bj["low"] = b.low;
      if (std::isfinite(b.high)) bj["high"] = b.high;  // JSON has no infinity: the last bin is open
    }
    j.push_back(bj);
  }
  return j;
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
  return {{"rmse_m", a.rmse_m},
          {"mae_m", a.mae_m},
          {"median_abs_m", a.median_abs_m},
          {"mean_error_m", a.mean_error_m},
          {"completeness", a.completeness},
          {"reference_pixels", a.reference_pixels},
          {"compared_pixels", a.compared_pixels}};
}

nlohmann::json ToJson(const ErrorBreakdown& b) {
  return {{"large_error_m", b.large_error_m},
          {"by_class", BinsJson(b.by_class)},
          {"by_distance", BinsJson(b.by_distance)},
          {"by_triangle_area", BinsJson(b.by_triangle_area)}};
}

nlohmann::json ToJson(const std::vector<SurfaceMetrics::DepthBand>& bands) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& b : bands) {
    j.push_back({{"from_m", b.from_m},
                 {"to_m", std::isfinite(b.to_m) ? nlohmann::json(b.to_m) : nlohmann::json(nullptr)},
                 {"samples", b.samples},
                 {"completeness", b.completeness}});
  }
  return j;
}

// "0-10 m 97.1 % (12 % of samples), ..." for the text and markdown reports.
std::string DepthBandsText(const SurfaceMetrics& s) {
  std::string text;
  for (const auto& b : s.completeness_by_depth) {
    const std::string range = std::isfinite(b.to_m) ? Fixed("%.0f", b.from_m) + "-" + Fixed("%.0f m", b.to_m)
                                                    : Fixed("beyond %.0f m", b.from_m);
    text +=
        (text.empty() ? "" : ", ") + range + " " + Fixed("%.1f %%", 100.0 * b.completeness) + " (" +
        Fixed("%.0f %%", s.truth_samples > 0 ? 100.0 * double(b.samples) / double(s.truth_samples) : 0.0) +
        " of samples)";
  }
  return text;
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
          {"truth_samples", s.truth_samples},
          {"completeness_by_depth", ToJson(s.completeness_by_depth)}};
}

nlohmann::json ToJson(const MeshEvaluation& e, bool per_frame) {
  nlohmann::json j{{"vertices", e.vertices},
                   {"triangles", e.triangles},
                   {"off_bytes", e.off_bytes},
                   {"frames", e.frames},
                   {"frames_unreadable", e.frames_unreadable}};
  if (e.frames_with_lidar > 0) j["lidar"] = ToJson(e.lidar);
  if (e.exact_depth) j["exact_depth"] = ToJson(*e.exact_depth);
  if (e.scene) j["scene_mesh"] = ToJson(*e.scene);
  // Both protocols, named by their filters ("lidar" / "exact_depth" above are the strict ones).
  nlohmann::json strict{{"filters", ProtocolFilters(e.strict_options)}};
  nlohmann::json paper{{"filters", ProtocolFilters(e.paper_options)}};
  if (e.frames_with_lidar > 0) {
    strict["lidar"] = ToJson(e.lidar);
    paper["lidar"] = ToJson(e.lidar_paper);
    paper["lidar"]["excluded_pixels"] = e.lidar_paper.excluded_pixels;
  }
  if (e.exact_depth) strict["exact_depth"] = ToJson(*e.exact_depth);
  if (e.exact_depth_paper) {
    paper["exact_depth"] = ToJson(*e.exact_depth_paper);
    paper["exact_depth"]["excluded_pixels"] = e.exact_depth_paper->excluded_pixels;
  }
  j["protocols"] = {{"strict", strict}, {"paper", paper}};
  if (e.lidar_static || e.exact_depth_static) {
    nlohmann::json static_scene{{"filters", ProtocolFilters(e.strict_options) + StaticSuffix(e)},
                                {"frames_with_labels", e.frames_with_labels}};
    if (e.lidar_static) static_scene["lidar"] = ToJson(*e.lidar_static);
    if (e.exact_depth_static) static_scene["exact_depth"] = ToJson(*e.exact_depth_static);
    j["protocols"]["static"] = static_scene;
  }
  nlohmann::json breakdown{{"class_source", e.class_source}};
  if (e.lidar_breakdown) breakdown["lidar"] = ToJson(*e.lidar_breakdown);
  if (e.exact_depth_breakdown) breakdown["exact_depth"] = ToJson(*e.exact_depth_breakdown);
  j["breakdown"] = breakdown;
  if (per_frame) {
    j["per_frame"] = nlohmann::json::array();
    for (const FrameAccuracy& f : e.per_frame) {
      nlohmann::json fj{{"frame_id", f.frame_id}};
      if (f.lidar) fj["lidar"] = ToJson(*f.lidar);
      if (f.exact_depth) fj["exact_depth"] = ToJson(*f.exact_depth);
      j["per_frame"].push_back(fj);
    }
  }
  return j;
}

void PrintEvaluation(const MeshEvaluation& e) {
  std::printf("mesh          %zu vertices, %zu triangles, %.3f MB as OFF\n", e.vertices, e.triangles,
              static_cast<double>(e.off_bytes) / 1e6);
  std::printf("frames        %lld evaluated (%lld with Velodyne, %lld with exact depth)\n",
              static_cast<long long>(e.frames), static_cast<long long>(e.frames_with_lidar),
              static_cast<long long>(e.frames_with_exact_depth));
  if (e.frames_unreadable > 0) {
    spdlog::warn("{} frame(s) could not be read and were not evaluated; first: {}", e.frames_unreadable,
                 e.first_unreadable);
  }
  if (e.frames_with_lidar > 0) {
    Print("vs Velodyne", e.lidar, "strict", e.strict_options);
    Print("  paper", e.lidar_paper, "paper", e.paper_options);
    if (e.lidar_static) Print("  static", *e.lidar_static, "static", e.strict_options, StaticSuffix(e));
  }
  if (e.exact_depth) Print("vs exact depth", *e.exact_depth, "strict", e.strict_options);
  if (e.exact_depth_paper) Print("  paper", *e.exact_depth_paper, "paper", e.paper_options);
  if (e.exact_depth_static)
    Print("  static", *e.exact_depth_static, "static", e.strict_options, StaticSuffix(e));
  if (e.scene) {
    const SurfaceMetrics& s = *e.scene;
    std::printf(
        "vs scene mesh accuracy %.1f %% of the area within tau = %.2f m (%.1f %% within %.2f m, %.1f %% "
        "beyond "
        "%.2f m, %.1f %% beyond %.2f m, mean %.3f m; area %.0f m2, %lld samples)\n",
        100.0 * s.accuracy, s.threshold_m, 100.0 * s.area_within_near, s.near_m, 100.0 * s.area_beyond_near,
        s.near_m, 100.0 * s.area_beyond_far, s.far_m, s.mean_distance_m, s.area_m2,
        static_cast<long long>(s.area_samples));
    std::printf(
        "              per vertex and centroid (every triangle once, whatever its size) %.1f %% within tau "
        "(mean %.3f m)\n",
        100.0 * s.vertex_accuracy, s.vertex_mean_distance_m);
    std::printf("              completeness %.1f %% (mean %.4f m) at tau = %.2f m\n", 100.0 * s.completeness,
                s.mean_completeness_m, s.threshold_m);
    if (!s.completeness_by_depth.empty()) {
      std::printf("              completeness by the depth the cameras saw the truth at: %s\n",
                  DepthBandsText(s).c_str());
    }
  }
}

std::vector<std::filesystem::path> WriteTopViews(const Mesh& mesh, const MeshEvaluation& e,
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
    io::WritePng(dir / "top_view_error.png",
                 RenderTopView(mesh, up, options, distance, e.camera_centers).image);
    written.push_back(dir / "top_view_error.png");
  }
  return written;
}

std::string EvaluationMarkdown(const MeshEvaluation& e) {
  std::string md = "# Mesh evaluation\n\n";
  md += "Mesh: " + std::to_string(e.vertices) + " vertices, " + std::to_string(e.triangles) + " triangles, " +
        Fixed("%.3f", static_cast<double>(e.off_bytes) / 1e6) +
        " MB as OFF. Frames: " + std::to_string(e.frames) + " evaluated (" +
        std::to_string(e.frames_with_lidar) + " with Velodyne, " + std::to_string(e.frames_with_exact_depth) +
        " with exact depth).\n\n";
  md +=
      "## Accuracy by protocol\n\n"
      "*strict*: every error of every reference pixel in the configured depth range (eval.min_depth_m .. "
      "eval.max_depth_m); *paper*: the 2018 authors' evaluator, reference depth <= 15 m and errors beyond 2 "
      "m left out (their count is in the last column; they still count as covered for completeness); "
      "*static* (when the frames have labels): the strict protocol without the pixels of movable classes "
      "(person, rider, car, truck, bus, train, motorcycle, bicycle) by the frames' own labels. Error = mesh "
      "depth - reference depth, camera-frame z on both sides.\n\n"
      "| protocol | reference | filters | RMSE (m) | MAE (m) | median abs (m) | bias (m) | completeness | "
      "pixels in figures | pixels left out |\n|---|---|---|---|---|---|---|---|---|---|\n";
  if (e.frames_with_lidar > 0) {
    md += ProtocolRow("strict", "Velodyne", e.lidar, e.strict_options);
    md += ProtocolRow("paper", "Velodyne", e.lidar_paper, e.paper_options);
    if (e.lidar_static)
      md += ProtocolRow("static", "Velodyne", *e.lidar_static, e.strict_options, StaticSuffix(e));
  }
  if (e.exact_depth) md += ProtocolRow("strict", "exact depth", *e.exact_depth, e.strict_options);
  if (e.exact_depth_paper) md += ProtocolRow("paper", "exact depth", *e.exact_depth_paper, e.paper_options);
  if (e.exact_depth_static) {
    md += ProtocolRow("static", "exact depth", *e.exact_depth_static, e.strict_options, StaticSuffix(e));
  }
  if (e.scene) {
    const SurfaceMetrics& s = *e.scene;
    md += "\nAgainst the exact scene mesh, by area: " + Fixed("%.1f %%", 100.0 * s.accuracy) + " within " +
          Fixed("%.2f m", s.threshold_m) + ", " + Fixed("%.1f %%", 100.0 * s.area_beyond_far) + " beyond " +
          Fixed("%.2f m", s.far_m) + "; completeness " + Fixed("%.1f %%", 100.0 * s.completeness) + ".\n";
    if (!s.completeness_by_depth.empty()) {
      md += "Completeness by the depth the cameras saw the truth at: " + DepthBandsText(s) + ".\n";
    }
  }
  if (e.lidar_breakdown || e.exact_depth_breakdown) {
    md += "\n## Where the errors come from (strict protocol, all evaluated frames)\n";
    if (e.lidar_breakdown) md += BreakdownMarkdown("Velodyne", *e.lidar_breakdown, e.class_source);
    if (e.exact_depth_breakdown)
      md += BreakdownMarkdown("exact depth", *e.exact_depth_breakdown, e.class_source);
  }
  if (!e.error_images.empty()) {
    md += "\n## Per-pixel error images\n\n";
    for (const FrameErrorImage& image : e.error_images) {
      char name[64];
      std::snprintf(name, sizeof(name), "error_%s_%06lld.png", image.reference.c_str(),
                    static_cast<long long>(image.frame_id));
      md += std::string("![frame ") + std::to_string(image.frame_id) + " vs " + image.reference + "](" +
            name + ")\n";
    }
  }
  return md;
}

std::vector<std::filesystem::path> WriteErrorImages(const MeshEvaluation& e,
                                                    const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> written;
  for (const FrameErrorImage& image : e.error_images) {
    char name[64];
    std::snprintf(name, sizeof(name), "error_%s_%06lld.png", image.reference.c_str(),
                  static_cast<long long>(image.frame_id));
    io::WritePng(dir / name, image.image);
    written.push_back(dir / name);
  }
  return written;
}

void WritePerFrameCsv(const MeshEvaluation& e, const std::filesystem::path& path) {
  io::AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "frame_id,lidar_rmse_m,lidar_mae_m,lidar_median_m,lidar_bias_m,lidar_completeness,"
         "exact_rmse_m,exact_mae_m,exact_median_m,exact_bias_m,exact_completeness\n";
  for (const FrameAccuracy& f : e.per_frame) {
    out << f.frame_id;
    CsvFields(out, f.lidar);
    CsvFields(out, f.exact_depth);
    out << '\n';
  }
  file.Commit();
}

}  // namespace semap::app
