// `semap table PATH...` (tools/cmd_table.cc parses it): the paper's incremental table. Each sequence is
// streamed twice through the engine (exhaustive mode), Original (O) and Incremental Simplification (PS); the
// table gives accuracy against Velodyne (RMSE, the paper's figure), frame rate, completeness, mesh size and
// the speed-up, with the paper's own figures beside them, in two protocols side by side (strict: every error
// in the configured depth range; paper: reference depth <= 15 m, |error| <= 2 m, as the authors' evaluator),
// and for generated sequences the by-area accuracy against the exact scene mesh. Every figure but the frame
// rates is `semap eval`'s of the run's written mesh.ply, whose report (eval.json, eval.md, eval_frames.csv,
// the pictures from above top_view*.png) each run's folder gets.
#include "app/paper/incremental_table.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/eval/eval_report.h"
#include "app/run/stream_run.h"

namespace semap::app {
namespace {

struct Row {
  std::string sequence;
  std::string method;
  double rmse_m = 0.0;        // strict protocol
  double rmse_paper_m = 0.0;  // paper protocol
  double fps = 0.0;           // the whole process: reading, depth, labels and the mapper
  double mapper_fps = 0.0;  // the mapper alone (simplification + map), the paper's rate: 1 / its time a frame
  double completeness = 0.0;
  double mesh_mb = 0.0;
  std::size_t triangles = 0;
  std::int64_t frames = 0;
  double exact_rmse_m = -1.0;  // against exact depth maps (generated sequences), < 0 = none
  double exact_rmse_paper_m = -1.0;
  std::string strict_filters, paper_filters;  // the protocols' filters, for the table's note
  bool has_lidar = false;  // false: the sequence has no Velodyne, RMSE and completeness are not defined
  std::optional<SurfaceMetrics> scene;  // against the exact scene mesh (generated sequences), by area
};

std::string Figure(bool defined, const char* format, double value) {
  if (!defined) return "–";
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

// The paper's incremental table (ICRA 2019, Table III): KITTI sequences 95 and 104.
struct PaperRow {
  const char* sequence;
  const char* method;
  double rmse_m;
  double fps;
};
constexpr PaperRow kPaper[] = {{"95", "O", 0.7135, 1.0082},
                               {"95", "PS", 0.7173, 1.5434},
                               {"104", "O", 0.7775, 0.4708},
                               {"104", "PS", 0.7846, 0.6397}};

// 1 / the mean time a frame of the simplification and the map stages; 0 when the run timed neither.
double MapperFps(const FrameStats& stats) {
  double ms = 0.0;
  for (const StageTiming& t : stats.stages) {
    if (t.name == "simplify" || t.name == "map") ms += t.mean_ms;
  }
  return ms > 0.0 ? 1000.0 / ms : 0.0;
}

std::pair<std::string, std::string> NameAndPath(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq != std::string::npos && eq > 0) return {arg.substr(0, eq), arg.substr(eq + 1)};
  std::filesystem::path p(arg);
  const std::string name = p.filename().empty() ? p.parent_path().filename().string() : p.filename().string();
  return {name, arg};
}

std::string Markdown(const std::vector<Row>& rows) {
  std::string md =
      "| sequence | method | RMSE strict (m) | RMSE paper (m) | f/s | speed-up | mapper f/s | "
      "mapper speed-up | "
      "completeness | mesh (MB, OFF) | "
      "triangles | frames | RMSE vs exact depth, strict (m) | RMSE vs exact depth, paper (m) | area (m²) | "
      "area within τ | within 0.5 m | beyond 2 m | mean distance (m) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  char line[896];
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    double speedup = 1.0, mapper_speedup = 1.0;
    for (const Row& o : rows) {
      if (o.sequence != r.sequence || o.method != "O") continue;
      if (o.fps > 0.0) speedup = r.fps / o.fps;
      if (o.mapper_fps > 0.0) mapper_speedup = r.mapper_fps / o.mapper_fps;
    }
    const bool scene = r.scene.has_value();
    const SurfaceMetrics s = r.scene.value_or(SurfaceMetrics());
    std::snprintf(
        line, sizeof(line),
        "| %s | %s | %s | %s | %.3f | %.2f× | %.3f | %.2f× | %s | %.2f | %zu | %lld | %s | %s | %s | %s | %s "
        "| %s "
        "| %s |\n",
        r.sequence.c_str(), r.method.c_str(), Figure(r.has_lidar, "%.4f", r.rmse_m).c_str(),
        Figure(r.has_lidar, "%.4f", r.rmse_paper_m).c_str(), r.fps, speedup, r.mapper_fps, mapper_speedup,
        Figure(r.has_lidar, "%.1f %%", 100.0 * r.completeness).c_str(), r.mesh_mb, r.triangles,
        static_cast<long long>(r.frames), Figure(r.exact_rmse_m >= 0.0, "%.4f", r.exact_rmse_m).c_str(),
        Figure(r.exact_rmse_paper_m >= 0.0, "%.4f", r.exact_rmse_paper_m).c_str(),
        Figure(scene, "%.0f", s.area_m2).c_str(), Figure(scene, "%.1f %%", 100.0 * s.accuracy).c_str(),
        Figure(scene, "%.1f %%", 100.0 * s.area_within_near).c_str(),
        Figure(scene, "%.1f %%", 100.0 * s.area_beyond_far).c_str(),
        Figure(scene, "%.2f", s.mean_distance_m).c_str());
    md += line;
  }
  if (!rows.empty()) {
    md +=
        "\nTwo protocols: *strict* = " + rows.front().strict_filters +
        " (every error counts); *paper* = " + rows.front().paper_filters +
        " (the 2018 authors' evaluator: larger errors left out). The paper's own figures below were measured "
        "with the paper protocol. *f/s* is the whole process's rate (reading, depth, labels, the mapper); "
        "*mapper f/s* is the rate of the simplification and the map on the depth and labels computed, what "
        "the paper's table measures: 1 / their mean time a frame on the map's threads.\n";
  }
  md +=
      "\nArea columns: the mesh's surface sampled uniformly by area against the exact scene mesh (generated "
      "sequences; τ = eval.surface_threshold_m). Pictures from above: NAME/METHOD/top_view*.png.\n";
  md +=
      "\nThe paper (KITTI, its Table III):\n\n| sequence | method | RMSE (m) | f/s | speed-up "
      "|\n|---|---|---|---|---|\n";
  for (const PaperRow& p : kPaper) {
    double o_fps = p.fps;
    for (const PaperRow& q : kPaper) {
      if (std::string(q.sequence) == p.sequence && std::string(q.method) == "O") o_fps = q.fps;
    }
    std::snprintf(line, sizeof(line), "| %s | %s | %.4f | %.4f | %.2f× |\n", p.sequence, p.method, p.rmse_m,
                  p.fps, p.fps / o_fps);
    md += line;
  }
  return md;
}

}  // namespace

bool WriteIncrementalTable(const TableRequest& args) {
  std::vector<Row> rows;
  for (const std::string& arg : args.datasets) {
    const auto [name, path] = NameAndPath(arg);
    for (const char* method : {"O", "PS"}) {
      std::vector<std::string> overrides = args.overrides;
      overrides.push_back(Override(&Config::simplify, &SimplifyOptions::method, method));
      overrides.push_back(Override(&Config::pipeline, &PipelineOptions::mode, "exhaustive"));
      overrides.push_back(Override(&Config::output, &io::OutputOptions::dir,
                                   (std::filesystem::path(args.out) / name / method).string()));
      if (args.frames > 0) {
        overrides.push_back(
            Override(&Config::input, &io::FrameSourceOptions::max_frames, std::to_string(args.frames)));
      }
      const Config config = LoadConfig(args.config_path, overrides);
      spdlog::info("table: {} ({}) with {}", name, path, method);
      StreamRunRequest request;
      request.dataset = path;
      request.progress_s = args.progress_s > 0.0 ? std::optional<double>(args.progress_s) : std::nullopt;
      request.evaluate = true;
      request.lcm = RunOutputs::Lcm::kOff;
      const StreamRunResult run = StreamRun(config, request);
      if (run.outcome != StreamRunOutcome::kDone) {
        spdlog::error("table: the run of {} with {} did not complete: no table", name, method);
        return false;
      }
      // A mesh without faces has no evaluation: its figures are undefined ("–"), its size nought.
      MeshEvaluation e;
      e.strict_options = config.eval;
      e.paper_options = PaperProtocol(config.eval);
      if (run.evaluation) e = *run.evaluation;
      Row r;
      r.sequence = name;
      r.method = method;
      r.has_lidar = e.frames_with_lidar > 0;
      r.rmse_m = e.lidar.rmse_m;
      r.rmse_paper_m = e.lidar_paper.rmse_m;
      r.strict_filters = ProtocolFilters(e.strict_options);
      r.paper_filters = ProtocolFilters(e.paper_options);
      r.completeness = e.lidar.completeness;
      r.fps = run.summary.final_stats.fps;
      r.mapper_fps = MapperFps(run.summary.final_stats);
      r.frames = run.summary.final_stats.frames_processed;
      r.mesh_mb = static_cast<double>(e.off_bytes) / 1e6;
      r.triangles = e.triangles;
      if (e.exact_depth) r.exact_rmse_m = e.exact_depth->rmse_m;
      if (e.exact_depth_paper) r.exact_rmse_paper_m = e.exact_depth_paper->rmse_m;
      r.scene = e.scene;
      spdlog::info(
          "table: {} {}: RMSE {:.4f} m strict, {:.4f} m paper, {:.3f} f/s ({:.3f} f/s the mapper alone), "
          "completeness {:.1f} %, {:.2f} MB",
          name, method, r.rmse_m, r.rmse_paper_m, r.fps, r.mapper_fps, 100.0 * r.completeness, r.mesh_mb);
      rows.push_back(r);
    }
  }
  const std::string md = Markdown(rows);
  std::printf("%s", md.c_str());
  std::filesystem::create_directories(args.out);
  const auto md_path = std::filesystem::path(args.out) / "table.md";
  const auto json_path = std::filesystem::path(args.out) / "table.json";
  std::ofstream(md_path) << md;
  nlohmann::json j = nlohmann::json::array();
  for (const Row& r : rows) {
    j.push_back({{"sequence", r.sequence},
                 {"method", r.method},
                 {"rmse_m", r.rmse_m},
                 {"fps", r.fps},
                 {"mapper_fps", r.mapper_fps},
                 {"completeness", r.completeness},
                 {"mesh_mb", r.mesh_mb},
                 {"triangles", r.triangles},
                 {"frames", r.frames},
                 {"exact_depth_rmse_m", r.exact_rmse_m},
                 {"has_lidar", r.has_lidar},
                 {"rmse_paper_m", r.rmse_paper_m},
                 {"exact_depth_rmse_paper_m", r.exact_rmse_paper_m},
                 {"protocols", {{"strict", r.strict_filters}, {"paper", r.paper_filters}}}});
    if (r.scene) j.back()["scene_mesh"] = ToJson(*r.scene);
  }
  std::ofstream(json_path) << j.dump(2) << "\n";
  if (!std::filesystem::is_regular_file(md_path) || !std::filesystem::is_regular_file(json_path)) {
    spdlog::error("could not write {} / {}", md_path.string(), json_path.string());
    return false;
  }
  spdlog::info("wrote {} and {}", md_path.string(), json_path.string());
  return true;
}

}  // namespace semap::app
