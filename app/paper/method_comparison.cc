// `semap compare PATH` (tools/cmd_compare.cc parses it): every simplification method on the same input,
// the paper's method plot.
// Mode `incremental` streams a sequence once per method through the engine; mode `single-frame` builds
// one batch map per frame (for the stereo-2015 frames, which have no poses), with depth and labels
// computed once per frame and shared by the methods. Writes compare.md, compare.csv and compare.png
// (mesh size vs RMSE, drawn by gnuplot, with the size of the mesh without ground and wall points as a
// vertical line); in incremental mode also the by-area accuracy against the exact scene mesh (generated
// sequences) and each method's report of its written mesh (METHOD/eval.json, eval.md, top_view*.png): in that
// mode every figure but the time is `semap eval`'s of the method's mesh.ply.
#include "app/paper/method_comparison.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include "app/eval/eval_report.h"
#include "app/run/stream_run.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/eval/depth_render.h"
#include "engine/map/batch_map.h"
#include "engine/pipeline/semap_stages.h"
#include "engine/simplify/simplify.h"
#include "io/frame_source.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

constexpr const char* kNoGroundWall = "no ground/wall";

struct Row {
  std::string method;
  double mesh_mb = 0.0;
  std::size_t triangles = 0;
  DepthAccuracy lidar;        // strict protocol (the configured filters)
  DepthAccuracy lidar_paper;  // paper protocol (<= 15 m, |error| <= 2 m)
  double seconds = 0.0;
  std::optional<SurfaceMetrics>
      scene;  // by area against the exact scene mesh (incremental, generated sequences)
  // Points in / kept per class role (ground, wall, other).
  std::map<ClassRole, std::pair<std::int64_t, std::int64_t>> roles;
};

// Keeps every point whose class is neither ground nor wall: the size of the mesh without them is the
// paper's vertical line (what removing the simplifiable classes entirely would give).
LabelledCloud DropGroundAndWall(const LabelledCloud& cloud, const ClassMap& class_map) {
  std::vector<std::uint32_t> keep;
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels.empty() || !class_map.IsTarget(cloud.labels[i])) keep.push_back(i);
  }
  return cloud.Subset(keep);
}

class DropGroundAndWallStage : public SimplifyStage {
 public:
  explicit DropGroundAndWallStage(ClassMap class_map) : class_map_(std::move(class_map)) {}
  LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) override {
    LabelledCloud kept = DropGroundAndWall(cloud, class_map_);
    std::map<Label, ClassPointCount> by_label;
    for (Label l : cloud.labels) ++by_label[l].in;
    for (Label l : kept.labels) ++by_label[l].kept;
    counts->clear();
    for (auto& [label, c] : by_label) {
      c.label = label;
      counts->push_back(c);
    }
    return kept;
  }

 private:
  ClassMap class_map_;
};

// Sums the per-frame class counts of a run by role.
class RoleCountSink : public PipelineSink {
 public:
  RoleCountSink(const ClassMap& class_map, Row* row) : class_map_(class_map), row_(row) {}
  void OnFrame(const FrameStats& stats, const MeshDelta&, const std::optional<Pose3d>&) override {
    for (const ClassPointCount& c : stats.class_counts) {
      auto& [in, kept] = row_->roles[class_map_.Role(c.label)];
      in += c.in;
      kept += c.kept;
    }
  }

 private:
  const ClassMap& class_map_;
  Row* row_;
};

std::vector<std::string> MethodNames(const CompareRequest& args) {
  if (!args.methods.empty()) return args.methods;
  std::vector<std::string> names;
  for (SimplifyMethod m : AllSimplifyMethods()) names.push_back(SimplifyMethodName(m));
  return names;
}

// One row per method, or none when a method's run did not complete (logged).
std::optional<std::vector<Row>> CompareIncremental(const CompareRequest& args, const ClassMap& class_map) {
  std::vector<Row> rows;
  std::vector<std::string> names = MethodNames(args);
  names.push_back(kNoGroundWall);
  for (const std::string& name : names) {
    const bool drop = name == kNoGroundWall;
    std::vector<std::string> overrides = args.overrides;
    if (!drop) overrides.push_back(Override(&Config::simplify, &SimplifyOptions::method, name));
    overrides.push_back(Override(&Config::pipeline, &PipelineOptions::mode, "exhaustive"));
    overrides.push_back(
        Override(&Config::output, &io::OutputOptions::dir,
                 (std::filesystem::path(args.out) / (drop ? "no_ground_wall" : name)).string()));
    if (args.frames > 0) {
      overrides.push_back(
          Override(&Config::input, &io::FrameSourceOptions::max_frames, std::to_string(args.frames)));
    }
    const Config config = LoadConfig(args.config_path, overrides);
    spdlog::info("compare: {}", name);
    Row row;
    row.method = name;
    RoleCountSink counts(class_map, &row);
    StreamRunRequest request;
    request.dataset = args.path;
    request.progress_s.reset();
    request.evaluate = true;
    request.lcm = RunOutputs::Lcm::kOff;
    if (drop) request.simplify = [&class_map] { return std::make_unique<DropGroundAndWallStage>(class_map); };
    request.extra_sinks = {&counts};
    const StreamRunResult run = StreamRun(config, request);
    if (run.outcome != StreamRunOutcome::kDone) {
      spdlog::error("compare: the run of {} did not complete: no comparison", name);
      return std::nullopt;
    }
    // A mesh without faces has no evaluation: its figures stay nought.
    const MeshEvaluation e = run.evaluation.value_or(MeshEvaluation());
    row.mesh_mb = static_cast<double>(e.off_bytes) / 1e6;
    row.triangles = e.triangles;
    row.lidar = e.lidar;
    row.lidar_paper = e.lidar_paper;
    row.seconds = run.summary.final_stats.elapsed_s;
    row.scene = e.scene;
    rows.push_back(row);
  }
  return rows;
}

std::vector<Row> CompareSingleFrame(const CompareRequest& args, const ClassMap& class_map) {
  Config config = LoadConfig(args.config_path, args.overrides);
  config.input.load_velodyne = true;
  if (args.frames > 0) config.input.max_frames = args.frames;
  auto source = io::OpenFrameSource(args.path, config.input);
  StereoLabelStage depth(config.depth, config.semantics, class_map);
  std::vector<std::string> names = MethodNames(args);
  names.push_back(kNoGroundWall);
  std::vector<Row> rows(names.size());
  std::vector<DepthAccuracyAccumulator> accuracy(names.size(), DepthAccuracyAccumulator(config.eval));
  std::vector<DepthAccuracyAccumulator> accuracy_paper(names.size(),
                                                       DepthAccuracyAccumulator(PaperProtocol(config.eval)));
  for (std::size_t m = 0; m < names.size(); ++m) rows[m].method = names[m];
  while (auto frame = source->Next()) {
    if (!frame->velodyne) {
      spdlog::warn("compare: frame {} has no Velodyne scan, skipped", frame->id);
      continue;
    }
    spdlog::info("compare: frame {}", frame->id);
    // One camera at the frame's own pose (identity when the dataset has none): a one-frame map.
    const Pose3d world_from_cam = frame->world_from_cam.value_or(Pose3d::Identity());
    Frame posed = *frame;
    posed.world_from_cam = world_from_cam;
    const LabelledCloud cloud = depth.Process(posed, nullptr);
    const cv::Mat lidar = LidarDepthImage(*frame->velodyne, frame->calibration, config.eval);
    for (std::size_t m = 0; m < names.size(); ++m) {
      const auto start = std::chrono::steady_clock::now();
      LabelledCloud kept;
      if (names[m] == kNoGroundWall) {
        kept = DropGroundAndWall(cloud, class_map);
      } else {
        SimplifyOptions options = config.simplify;
        options.method = SimplifyMethodFromName(names[m]);
        WindowedSimplifyStage simplify(options, class_map);
        std::vector<ClassPointCount> counts;
        kept = simplify.Process(cloud, &counts);
      }
      for (Label l : cloud.labels) ++rows[m].roles[class_map.Role(l)].first;
      for (Label l : kept.labels) ++rows[m].roles[class_map.Role(l)].second;
      const Mesh mesh = BuildBatchMap(config.map, kept, {}).mesh;
      rows[m].seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rows[m].mesh_mb += static_cast<double>(io::OffSizeBytes(mesh)) / 1e6;
      rows[m].triangles += mesh.num_triangles();
      const cv::Mat mesh_depth = RenderDepth(mesh, frame->calibration, world_from_cam);
      accuracy[m].Add(lidar, mesh_depth);
      accuracy_paper[m].Add(lidar, mesh_depth);
    }
  }
  for (std::size_t m = 0; m < names.size(); ++m) {
    rows[m].lidar = accuracy[m].Result();
    rows[m].lidar_paper = accuracy_paper[m].Result();
  }
  return rows;
}

double KeptShare(const Row& r, ClassRole role) {
  const auto it = r.roles.find(role);
  if (it == r.roles.end() || it->second.first == 0) return 1.0;
  return double(it->second.second) / double(it->second.first);
}

void WriteOutputs(const CompareRequest& args, const std::vector<Row>& rows,
                  const DepthAccuracyOptions& strict) {
  const std::filesystem::path out(args.out);
  std::filesystem::create_directories(out);
  std::string md =
      "| method | mesh (MB, OFF) | triangles | RMSE strict (m) | RMSE paper (m) | MAE strict (m) | "
      "completeness | "
      "kept ground | kept wall | kept other | time (s) | area (m²) | area within τ | within 0.5 m | beyond 2 "
      "m | "
      "mean distance (m) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::ofstream csv(out / "compare.csv");
  csv << "method,mesh_mb,triangles,rmse_m,mae_m,completeness,kept_ground,kept_wall,kept_other,seconds,"
         "area_m2,area_accuracy,area_within_near,area_beyond_far,mean_distance_m,rmse_paper_m,mae_paper_m\n";
  char line[768];
  for (const Row& r : rows) {
    // The by-area figures exist for incremental runs of generated sequences: "–" / nan elsewhere.
    const auto figure = [&](const char* format, double value) {
      if (!r.scene) return std::string("–");
      char text[32];
      std::snprintf(text, sizeof(text), format, value);
      return std::string(text);
    };
    const SurfaceMetrics s = r.scene.value_or(SurfaceMetrics());
    std::snprintf(line, sizeof(line),
                  "| %s | %.2f | %zu | %.4f | %.4f | %.4f | %.1f %% | %.0f %% | %.0f %% | %.0f %% | %.1f | "
                  "%s | %s | %s "
                  "| %s | %s |\n",
                  r.method.c_str(), r.mesh_mb, r.triangles, r.lidar.rmse_m, r.lidar_paper.rmse_m,
                  r.lidar.mae_m, 100.0 * r.lidar.completeness, 100.0 * KeptShare(r, ClassRole::kGround),
                  100.0 * KeptShare(r, ClassRole::kWall), 100.0 * KeptShare(r, ClassRole::kKeep), r.seconds,
                  figure("%.0f", s.area_m2).c_str(), figure("%.1f %%", 100.0 * s.accuracy).c_str(),
                  figure("%.1f %%", 100.0 * s.area_within_near).c_str(),
                  figure("%.1f %%", 100.0 * s.area_beyond_far).c_str(),
                  figure("%.2f", s.mean_distance_m).c_str());
    md += line;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    csv << '"' << r.method << '"' << ',' << r.mesh_mb << ',' << r.triangles << ',' << r.lidar.rmse_m << ','
        << r.lidar.mae_m << ',' << r.lidar.completeness << ',' << KeptShare(r, ClassRole::kGround) << ','
        << KeptShare(r, ClassRole::kWall) << ',' << KeptShare(r, ClassRole::kKeep) << ',' << r.seconds << ','
        << (r.scene ? s.area_m2 : nan) << ',' << (r.scene ? s.accuracy : nan) << ','
        << (r.scene ? s.area_within_near : nan) << ',' << (r.scene ? s.area_beyond_far : nan) << ','
        << (r.scene ? s.mean_distance_m : nan) << ',' << r.lidar_paper.rmse_m << ',' << r.lidar_paper.mae_m
        << '\n';
  }
  md += "\nTwo protocols against Velodyne: *strict* = " + ProtocolFilters(strict) +
        " (every error counts); *paper* = " + ProtocolFilters(PaperProtocol(strict)) +
        " (the 2018 authors' evaluator: larger errors left out). The plot "
        "(compare.png) has both.\n";
  csv.close();
  std::printf("%s", md.c_str());
  std::ofstream(out / "compare.md") << md;

  // The plot: gnuplot from Debian (gnuplot-nox), called on a script written beside the data. Two panels, the
  // strict and the paper protocol, each autoscaled; the semantic methods and the non-semantic baselines in
  // two colours, so that the paper's claim (at equal size the semantic methods are more accurate) can be
  // read off.
  double line_mb = 0.0;
  for (const Row& r : rows) {
    if (r.method == kNoGroundWall) line_mb = r.mesh_mb;
  }
  // Column 5: 0 = no simplification (O), 1 = non-semantic baseline, 2 = semantic method.
  std::ofstream dat(out / "compare_plot.dat");
  dat << "# method mesh_mb rmse_strict_m rmse_paper_m kind(0 O, 1 baseline, 2 semantic)\n";
  for (const Row& r : rows) {
    if (r.method == kNoGroundWall) continue;
    const SimplifyMethod method = SimplifyMethodFromName(r.method);
    const int kind = method == SimplifyMethod::kOriginal ? 0 : IsSemanticMethod(method) ? 2 : 1;
    dat << '"' << r.method << "\" " << r.mesh_mb << ' ' << r.lidar.rmse_m << ' ' << r.lidar_paper.rmse_m
        << ' ' << kind << '\n';
  }
  dat.close();
  const auto panel = [&](int column, const std::string& protocol) {
    return "set ylabel 'RMSE vs Velodyne, " + protocol + " (m)'\n" +
           "plot 'compare_plot.dat' using 2:($5 == 2 ? $" + std::to_string(column) +
           " : 1/0) with points pt 7 ps 1.5 lc rgb '#1f77b4' title 'semantic', " + "'' using 2:($5 == 1 ? $" +
           std::to_string(column) +
           " : 1/0) with points pt 5 ps 1.3 lc rgb '#ff7f0e' title 'non-semantic baseline', " +
           "'' using 2:($5 == 0 ? $" + std::to_string(column) +
           " : 1/0) with points pt 9 ps 1.8 lc rgb 'black' title 'O (no simplification)', " +
           "'' using 2:" + std::to_string(column) + ":1 with labels offset 0,0.9 font ',9' notitle\n";
  };
  std::ofstream gp(out / "compare.gp");
  gp << "set terminal pngcairo size 1400,600 noenhanced\nset output 'compare.png'\n"
     << "set multiplot layout 1,2 title 'Mesh size vs accuracy (" << args.mode << ": "
     << std::filesystem::path(args.path).filename().string() << ")'\n"
     << "set xlabel 'mesh size (MB, OFF)'\nset grid\nset key below horizontal\nset xrange [0:*]\n"
     << "set offsets 0, 0, graph 0.08, graph 0.05\n"
     << "set arrow 1 from " << line_mb << ", graph 0 to " << line_mb << ", graph 1 nohead lc rgb 'red' dt 2\n"
     << "set label 1 'without ground and wall' at " << line_mb
     << ", graph 0.97 offset 0.5,0 tc rgb 'red' font ',9'\n"
     << "set title 'strict: every error counts'\n"
     << panel(3, "strict") << "set title 'paper protocol: <= 15 m, |error| <= 2 m'\n"
     << panel(4, "paper") << "unset multiplot\n";
  gp.close();
  const std::string cmd = "cd '" + out.string() + "' && gnuplot compare.gp";
  if (std::system(cmd.c_str()) != 0) {
    spdlog::warn("gnuplot failed (is gnuplot-nox installed?): no compare.png; the data is in compare.csv");
  } else {
    spdlog::info("wrote {}", (out / "compare.png").string());
  }
  spdlog::info("wrote {} and {}", (out / "compare.md").string(), (out / "compare.csv").string());
}

}  // namespace

bool CompareMethods(const CompareRequest& args) {
  for (const std::string& m : args.methods) SimplifyMethodFromName(m);  // unknown names fail before any work
  const ClassMap class_map =
      io::OpenFrameSource(args.path, LoadConfig(args.config_path, args.overrides).input)->class_map();
  const std::optional<std::vector<Row>> rows =
      args.mode == "incremental" ? CompareIncremental(args, class_map) : CompareSingleFrame(args, class_map);
  if (!rows) return false;
  WriteOutputs(args, *rows, LoadConfig(args.config_path, args.overrides).eval);
  return true;
}

}  // namespace semap::app
