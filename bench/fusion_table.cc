// semap_fusion_table: what fusing the frames gains over any one of them. For each frame of a sequence, the
// SGBM depth map the map is built from (as semap_stereo_bound reads it) and the mesh rendered into the same
// camera are compared with the same reference depths (the Velodyne, and the exact depth of generated
// sequences), per reference-depth bin: RMSE, median |error|, bias (mean error, > 0 = behind the reference)
// and completeness, side by side. Each table is given for every pixel and for the static scene alone: the
// pixels whose class is not a movable one (person, rider, car, truck, bus, train, motorcycle, bicycle), so
// that a map of what stays is not judged by objects that left. The class of a pixel is the frame's own:
// its label image, or with semantics.source: enet the segmenter's labels of the frame (every frame); only
// without either, the label of the mesh triangle hit (which cannot tell a car that left: the mesh shows
// the road behind it there). A third table judges the static scene on the pixels both depth maps cover, so
// that neither is judged on pixels the other leaves out (the mesh covers more, and harder, pixels). A fourth
// splits those pixels by the angle between the pixel's ray and the normal of the mesh triangle it hits
// (0° = the surface faces the camera, 90° = seen edge-on): a surface seen at a grazing angle turns a small
// error across it into a large one along the ray, 1 / cos of that angle. Beside the depth figures it gives
// each side's median distance to the reference point across the surface: |depth error| · |ray| / z ·
// cos(angle), the depth error with that magnification taken out. A fifth splits the static pixels by the
// frame's class of the pixel and reference-depth bin, with each row's share of the mesh's squared error
// (which classes make the strict RMSE), and --per-frame adds each frame's static RMSE, all depths and 20-40 m
// (which frames make it).
//
// With plane_sweep.stereo_past_frames the input is SGBM with the sweep beside it, as in a run, and
// --sweep-picture-frame F --sweep-picture PNG draws what the sweep changed in frame F.
//
// Usage: semap_fusion_table SEQUENCE --mesh MESH.ply [--frames N] [--per-frame] [--config FILE]
//        [--set key=value ...] [--sweep-picture-frame F --sweep-picture PNG]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/eval/mesh_evaluation.h"
#include "bench/sequence_args.h"
#include "bench/stats.h"
#include "engine/depth/stereo_depth.h"
#include "engine/depth/stereo_sweep.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/eval/depth_render.h"
#include "engine/eval/error_breakdown.h"
#include "engine/semantics/segmenter.h"
#include "io/frame_source.h"
#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"

namespace {

using semap::DepthAccuracy;
using semap::DepthAccuracyAccumulator;
using semap::DepthAccuracyOptions;

// The bins' edges (m) of reference depth.
constexpr double kEdgesM[] = {0.0, 10.0, 20.0, 30.0, 40.0};
// One more row: the far surfaces, where a stereo pair's depth is weakest.
constexpr double kFarM[] = {20.0, 40.0};

// The accumulators of one reference and one pixel selection: per bin and in total, input and mesh.
struct Table {
  explicit Table(const DepthAccuracyOptions& strict) {
    for (int side = 0; side < 2; ++side) {
      total[side].emplace_back(strict);
      DepthAccuracyOptions far_options = strict;
      far_options.min_depth_m = std::max(strict.min_depth_m, kFarM[0]);
      far_options.max_depth_m = std::min(strict.max_depth_m, kFarM[1]);
      far[side].emplace_back(far_options);
      for (std::size_t b = 0; b + 1 < std::size(kEdgesM); ++b) {
        DepthAccuracyOptions o = strict;
        o.min_depth_m = std::max(strict.min_depth_m, kEdgesM[b]);
        o.max_depth_m = std::min(strict.max_depth_m, kEdgesM[b + 1]);
        bins[side].emplace_back(o);
      }
    }
  }
  void Add(const cv::Mat& reference, const cv::Mat& input, const cv::Mat& mesh) {
    const cv::Mat* depth[2] = {&input, &mesh};
    for (int side = 0; side < 2; ++side) {
      total[side][0].Add(reference, *depth[side]);
      far[side][0].Add(reference, *depth[side]);
      for (auto& b : bins[side]) b.Add(reference, *depth[side]);
    }
  }
  std::vector<DepthAccuracyAccumulator> total[2], far[2], bins[2];
};

void PrintRow(const std::string& name, const DepthAccuracy& in, const DepthAccuracy& mesh) {
  std::printf("| %s | %.3f | %.3f | %+.3f | %.1f %% | %.3f | %.3f | %+.3f | %.1f %% | %.2f |\n", name.c_str(),
              in.rmse_m, in.median_abs_m, in.mean_error_m, 100.0 * in.completeness, mesh.rmse_m,
              mesh.median_abs_m, mesh.mean_error_m, 100.0 * mesh.completeness,
              in.rmse_m > 0.0 ? mesh.rmse_m / in.rmse_m : 0.0);
}

void Print(const std::string& title, const Table& t) {
  std::printf("\n%s\n\n", title.c_str());
  std::printf(
      "| reference depth | SGBM RMSE (m) | SGBM median (m) | SGBM bias (m) | SGBM completeness | mesh RMSE "
      "(m) | "
      "mesh median (m) | mesh bias (m) | mesh completeness | mesh / SGBM RMSE |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t b = 0; b < t.bins[0].size(); ++b) {
    char name[32];
    std::snprintf(name, sizeof(name), "%.0f-%.0f m", kEdgesM[b], kEdgesM[b + 1]);
    PrintRow(name, t.bins[0][b].Result(), t.bins[1][b].Result());
  }
  char far_name[32];
  std::snprintf(far_name, sizeof(far_name), "%.0f-%.0f m", kFarM[0], kFarM[1]);
  PrintRow(far_name, t.far[0][0].Result(), t.far[1][0].Result());
  PrintRow("all", t.total[0][0].Result(), t.total[1][0].Result());
}

// `reference` with only the pixels where both depth maps have a depth (> 0 and finite): the input and the
// mesh judged on the same pixels, whatever each covers.
cv::Mat WhereBothCover(const cv::Mat& reference, const cv::Mat& input, const cv::Mat& mesh) {
  cv::Mat out = reference.clone();
  const auto covers = [](float z) { return std::isfinite(z) && z > 0.0f; };
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      if (!covers(input.at<float>(v, u)) || !covers(mesh.at<float>(v, u))) out.at<float>(v, u) = 0.0f;
    }
  }
  return out;
}

// The three tables of one reference: every pixel, the static scene, and the static scene where both depth
// maps cover.
struct ReferenceTables {
  explicit ReferenceTables(const DepthAccuracyOptions& strict)
      : all(strict), static_scene(strict), common(strict) {}
  void Add(const cv::Mat& reference, const cv::Mat& static_reference, const cv::Mat& input,
           const cv::Mat& mesh) {
    all.Add(reference, input, mesh);
    static_scene.Add(static_reference, input, mesh);
    common.Add(WhereBothCover(static_reference, input, mesh), input, mesh);
  }
  void Print(const std::string& reference, int frames) const {
    ::Print(reference + ", every pixel (" + std::to_string(frames) + " frames)", all);
    ::Print(reference + ", static scene (pixels of movable classes left out)", static_scene);
    ::Print(reference + ", static scene, only the pixels both the SGBM depth and the mesh cover", common);
  }
  Table all, static_scene, common;
};

// The static pixels both depth maps cover (within the strict depth range), by the incidence angle of the
// mesh surface at the pixel (see the header).
class IncidenceTable {
 public:
  explicit IncidenceTable(const DepthAccuracyOptions& strict) : strict_(strict) {}
  void Add(const cv::Mat& static_reference, const cv::Mat& input, const cv::Mat& mesh_depth,
           const cv::Mat& triangle, const semap::Mesh& mesh, const semap::StereoCalibration& k,
           const semap::Pose3d& world_from_cam) {
    const Eigen::Matrix3d cam_from_world = world_from_cam.linear().transpose();
    for (int v = 0; v < static_reference.rows; ++v) {
      for (int u = 0; u < static_reference.cols; ++u) {
        const double z = static_reference.at<float>(v, u);
        const float zi = input.at<float>(v, u), zm = mesh_depth.at<float>(v, u);
        const int t = triangle.at<int>(v, u);
        if (!(z >= strict_.min_depth_m && z <= strict_.max_depth_m) || t < 0) continue;
        if (!(std::isfinite(zi) && zi > 0.0f && std::isfinite(zm) && zm > 0.0f)) continue;
        const auto& tri = mesh.triangles[std::size_t(t)];
        const Eigen::Vector3d normal_world = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                                                 .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
        if (normal_world.squaredNorm() == 0.0) continue;
        const Eigen::Vector3d normal = (cam_from_world * normal_world).normalized();
        const Eigen::Vector3d ray((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0);  // at z = 1
        const double cos_incidence = std::abs(normal.dot(ray.normalized()));
        const double angle_deg = std::acos(std::min(1.0, cos_incidence)) * 180.0 / M_PI;
        const int b = semap::bench::BinOf(kAngleEdgesDeg, angle_deg);
        const int r = semap::bench::BinOf(kRangeEdgesM, z);
        if (b < 0 || r < 0) continue;
        const double across = ray.norm() * cos_incidence;  // distance across the surface per metre of depth
        Bin& bin = bins_[std::size_t(r)][std::size_t(b)];
        const double ei = double(zi) - z, em = double(zm) - z;
        bin.input_sq += ei * ei;
        bin.mesh_sq += em * em;
        bin.input_abs.push_back(std::abs(ei));
        bin.mesh_abs.push_back(std::abs(em));
        bin.input_across.push_back(std::abs(ei) * across);
        bin.mesh_across.push_back(std::abs(em) * across);
      }
    }
  }
  void Print(const std::string& title) const {
    std::printf("\n%s\n\n", title.c_str());
    std::printf(
        "| reference depth | incidence | share of pixels | SGBM RMSE (m) | SGBM median (m) | mesh RMSE (m) | "
        "mesh median (m) | SGBM median across (m) | mesh median across (m) |\n"
        "|---|---|---|---|---|---|---|---|---|\n");
    std::size_t total = 0;
    for (const auto& range : bins_) {
      for (const Bin& bin : range) total += bin.input_abs.size();
    }
    for (std::size_t r = 0; r < bins_.size(); ++r) {
      for (std::size_t b = 0; b < bins_[r].size(); ++b) {
        const Bin& bin = bins_[r][b];
        const double n = double(bin.input_abs.size());
        if (n == 0) continue;
        char range[32];
        if (r + 2 < std::size(kRangeEdgesM)) {
          std::snprintf(range, sizeof(range), "%.0f-%.0f m", kRangeEdgesM[r], kRangeEdgesM[r + 1]);
        } else {
          std::snprintf(range, sizeof(range), "%.0f m and beyond", kRangeEdgesM[r]);
        }
        std::printf("| %s | %.0f-%.0f° | %.1f %% | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", range,
                    kAngleEdgesDeg[b], kAngleEdgesDeg[b + 1], 100.0 * n / double(total),
                    std::sqrt(bin.input_sq / n), semap::bench::Median(bin.input_abs),
                    std::sqrt(bin.mesh_sq / n), semap::bench::Median(bin.mesh_abs),
                    semap::bench::Median(bin.input_across), semap::bench::Median(bin.mesh_across));
      }
    }
  }

 private:
  // The last edge holds 90° itself.
  static constexpr double kAngleEdgesDeg[] = {0.0, 45.0, 70.0, 80.0, 85.0, 90.0001};
  // Reference depth: the paper protocol's range, and beyond it (the strict range's end is not a bound here).
  static constexpr double kRangeEdgesM[] = {0.0, semap::kPaperMaxDepthM,
                                            std::numeric_limits<double>::infinity()};
  struct Bin {
    double input_sq = 0.0, mesh_sq = 0.0;
    std::vector<double> input_abs, mesh_abs, input_across, mesh_across;
  };
  DepthAccuracyOptions strict_;
  std::array<std::array<Bin, std::size(kAngleEdgesDeg) - 1>, std::size(kRangeEdgesM) - 1> bins_;
};

// The static pixels (within the strict depth range) by the frame's class of the pixel and reference-depth
// bin: each depth map's RMSE on the pixels it covers, and the row's share of the mesh's squared error.
class ClassTable {
 public:
  explicit ClassTable(const DepthAccuracyOptions& strict) : strict_(strict) {}
  void Add(const cv::Mat& static_reference, const cv::Mat& classes, const cv::Mat& input,
           const cv::Mat& mesh) {
    const cv::Mat* depth[2] = {&input, &mesh};
    for (int v = 0; v < static_reference.rows; ++v) {
      for (int u = 0; u < static_reference.cols; ++u) {
        const double z = static_reference.at<float>(v, u);
        if (!(z >= strict_.min_depth_m && z <= strict_.max_depth_m)) continue;
        const int b = semap::bench::BinOf(kEdgesM, z);
        if (b < 0) continue;
        Row& row = rows_[{classes.at<int>(v, u), b}];
        for (int side = 0; side < 2; ++side) {
          const float zs = depth[side]->at<float>(v, u);
          if (!(std::isfinite(zs) && zs > 0.0f)) continue;
          const double e = double(zs) - z;
          row.sq[side] += e * e;
          ++row.n[side];
        }
      }
    }
  }
  void Print(const std::string& title, const semap::ClassMap& class_map) const {
    std::printf("\n%s\n\n", title.c_str());
    std::printf(
        "| class | reference depth | SGBM pixels | SGBM RMSE (m) | mesh pixels | mesh RMSE (m) | "
        "share of the mesh's squared error |\n|---|---|---|---|---|---|---|\n");
    double total_sq = 0.0;
    for (const auto& [key, row] : rows_) total_sq += row.sq[1];
    for (const auto& [key, row] : rows_) {
      if (row.n[1] == 0 || row.sq[1] < kMinShareShown * total_sq) continue;
      const auto [label, b] = key;
      const std::string name = label >= 0 && class_map.Contains(semap::Label(label))
                                   ? class_map.Get(semap::Label(label)).name
                                   : "none";
      std::printf("| %s | %.0f-%.0f m | %lld | %.3f | %lld | %.3f | %.1f %% |\n", name.c_str(), kEdgesM[b],
                  kEdgesM[b + 1], static_cast<long long>(row.n[0]),
                  row.n[0] > 0 ? std::sqrt(row.sq[0] / double(row.n[0])) : 0.0,
                  static_cast<long long>(row.n[1]), std::sqrt(row.sq[1] / double(row.n[1])),
                  100.0 * row.sq[1] / total_sq);
    }
    std::printf("(rows under %.0f %% of the mesh's squared error left out)\n", 100.0 * kMinShareShown);
  }

 private:
  static constexpr double kMinShareShown = 0.01;
  struct Row {
    double sq[2] = {0.0, 0.0};
    std::int64_t n[2] = {0, 0};
  };
  DepthAccuracyOptions strict_;
  std::map<std::pair<int, int>, Row> rows_;
};

// One table row per frame: the static scene's RMSE of each depth map over the strict range and over 20-40 m.
std::string FrameRow(std::int64_t frame_id, const cv::Mat& static_reference, const cv::Mat& input,
                     const cv::Mat& mesh, const DepthAccuracyOptions& strict) {
  constexpr double kFarFromM = 20.0;
  double sq[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  std::int64_t n[2][2] = {{0, 0}, {0, 0}};
  const cv::Mat* depth[2] = {&input, &mesh};
  for (int v = 0; v < static_reference.rows; ++v) {
    for (int u = 0; u < static_reference.cols; ++u) {
      const double z = static_reference.at<float>(v, u);
      if (!(z >= strict.min_depth_m && z <= strict.max_depth_m)) continue;
      for (int side = 0; side < 2; ++side) {
        const float zs = depth[side]->at<float>(v, u);
        if (!(std::isfinite(zs) && zs > 0.0f)) continue;
        const double e = double(zs) - z;
        for (int far = 0; far < (z >= kFarFromM ? 2 : 1); ++far) {
          sq[side][far] += e * e;
          ++n[side][far];
        }
      }
    }
  }
  const auto rmse = [&](int side, int far) {
    return n[side][far] > 0 ? std::sqrt(sq[side][far] / double(n[side][far])) : 0.0;
  };
  char row[128];
  std::snprintf(row, sizeof(row), "| %lld | %.3f | %.3f | %.3f | %.3f |\n", static_cast<long long>(frame_id),
                rmse(0, 0), rmse(1, 0), rmse(0, 1), rmse(1, 1));
  return row;
}

// A picture of what the sweep changed in one frame: on top, the left image with the pixels whose depth the
// sweep gave in green; below, the Velodyne's pixels among those, green where the sweep's depth is nearer the
// Velodyne's than SGBM's was, red where it is farther, and the Velodyne's other pixels grey.
void WriteSweepPicture(const std::string& path, const cv::Mat& left, const cv::Mat& sgbm_m,
                       const cv::Mat& combined_m, const cv::Mat& lidar_m) {
  cv::Mat grey = left, base;
  if (left.channels() == 3) cv::cvtColor(left, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(grey, base, cv::COLOR_GRAY2BGR);
  cv::Mat top = base * 0.6, bottom = base * 0.3;
  const cv::Vec3b green(0, 220, 0), red(0, 0, 255), grey_point(160, 160, 160);
  for (int v = 0; v < base.rows; ++v) {
    for (int u = 0; u < base.cols; ++u) {
      const float a = sgbm_m.at<float>(v, u), b = combined_m.at<float>(v, u), z = lidar_m.at<float>(v, u);
      const bool changed = a > 0.0f && b > 0.0f && a != b;
      if (changed) top.at<cv::Vec3b>(v, u) = 0.5 * top.at<cv::Vec3b>(v, u) + 0.5 * green;
      if (!(z > 0.0f)) continue;
      cv::Vec3b colour = grey_point;
      if (changed) colour = std::abs(b - z) < std::abs(a - z) ? green : red;
      cv::circle(bottom, cv::Point(u, v), 1, colour, cv::FILLED);
    }
  }
  cv::Mat both;
  cv::vconcat(top, bottom, both);
  if (!cv::imwrite(path, both)) throw std::runtime_error("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Per-frame SGBM depth against the fused mesh, per reference-depth bin (Velodyne, exact depth)"};
  semap::bench::SequenceArgs args;
  std::string mesh_path;
  args.AddTo(app, "sequence with Velodyne scans or exact depth (KITTI, generated)");
  app.add_option("--mesh", mesh_path, "the mesh of `semap run` on that sequence (.ply or .off)")->required();
  bool per_frame = false;
  app.add_flag("--per-frame", per_frame,
               "also print each frame's static RMSE against the Velodyne (all depths, 20-40 m)");
  int picture_frame = -1;
  std::string picture_path;
  app.add_option("--sweep-picture-frame", picture_frame,
                 "with plane_sweep.stereo_past_frames: the frame whose picture of what the sweep changed "
                 "--sweep-picture writes");
  app.add_option("--sweep-picture", picture_path, "that picture's PNG path");
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    const std::string& sequence = args.sequence;
    const semap::io::FrameSourceOptions input = args.Input(config, true);
    const semap::io::SequenceInfo info = semap::io::DescribeDataset(sequence, input);
    auto source = semap::io::OpenFrameSource(sequence, input);
    const std::vector<int> movable = semap::MovableClassIds(source->class_map());
    const semap::Mesh mesh = semap::io::ReadMesh(mesh_path);
    const std::vector<int> triangle_labels = semap::TriangleLabels(mesh);
    const semap::StereoDepth depth(config.depth);
    // With plane_sweep.stereo_past_frames, the map's input is SGBM with the sweep beside it, as in a run.
    const semap::PlaneSweepDepth stereo_sweep(semap::StereoFrameSweepOptions(config.plane_sweep));
    semap::PastFrameViews past_views(config.plane_sweep.stereo_past_frames);
    semap::StereoSweepCounts sweep_counts;
    std::unique_ptr<semap::Segmenter> segmenter;
    if (config.semantics.source == semap::LabelSource::kEnet)
      segmenter = semap::MakeSegmenter(config.semantics);
    const DepthAccuracyOptions strict = config.eval;
    ReferenceTables lidar_tables(strict), exact_tables(strict);
    IncidenceTable lidar_incidence(strict), exact_incidence(strict);
    ClassTable lidar_classes(strict);
    std::string frame_rows;
    int with_lidar = 0, with_exact = 0;
    while (auto frame = source->Next()) {
      past_views.Attach(&*frame);
      if (!frame->world_from_cam) continue;
      const auto exact_path = semap::app::ExactDepthPath(info, frame->id);
      if (!frame->velodyne && !exact_path) continue;
      const semap::DisparityResult d =
          semap::StereoSweepDisparity(*frame, depth, stereo_sweep, &sweep_counts);
      const cv::Mat stereo = depth.ToDepthView(*frame, d.disparity_px, d.confidence).depth_m;
      const semap::DepthAndTriangles rendered =
          semap::RenderDepthAndTriangles(mesh, frame->calibration, *frame->world_from_cam);
      if (segmenter && frame->labels.empty()) frame->labels = segmenter->Segment(frame->left);
      const cv::Mat classes = semap::PixelClasses(frame->labels, rendered.triangle, triangle_labels);
      if (frame->velodyne) {
        const cv::Mat lidar = semap::LidarDepthImage(*frame->velodyne, frame->calibration, strict);
        if (frame->id == picture_frame && !picture_path.empty()) {
          const semap::DisparityResult alone = depth.Compute(frame->left, frame->right);
          WriteSweepPicture(picture_path, frame->left,
                            depth.ToDepthView(*frame, alone.disparity_px, alone.confidence).depth_m, stereo,
                            lidar);
        }
        const cv::Mat lidar_static = semap::WithoutMovable(lidar, classes, movable);
        lidar_tables.Add(lidar, lidar_static, stereo, rendered.depth);
        lidar_incidence.Add(lidar_static, stereo, rendered.depth, rendered.triangle, mesh, frame->calibration,
                            *frame->world_from_cam);
        lidar_classes.Add(lidar_static, classes, stereo, rendered.depth);
        if (per_frame) frame_rows += FrameRow(frame->id, lidar_static, stereo, rendered.depth, strict);
        ++with_lidar;
      }
      if (exact_path) {
        const cv::Mat exact = semap::io::ReadDepthPngMm(*exact_path);
        const cv::Mat exact_static = semap::WithoutMovable(exact, classes, movable);
        exact_tables.Add(exact, exact_static, stereo, rendered.depth);
        exact_incidence.Add(exact_static, stereo, rendered.depth, rendered.triangle, mesh, frame->calibration,
                            *frame->world_from_cam);
        ++with_exact;
      }
    }
    std::printf(
        "Fusion: per-frame SGBM depth (the map's input) against the mesh %s, %s, strict protocol (%s)\n",
        mesh_path.c_str(), sequence.c_str(), semap::ProtocolFilters(strict).c_str());
    if (config.plane_sweep.stereo_past_frames > 0) {
      const double all = static_cast<double>(sweep_counts.sgbm + sweep_counts.replaced);
      std::printf(
          "SGBM with the plane sweep over %d earlier frames: %.1f %% of SGBM's pixels take the sweep's "
          "depth\n",
          config.plane_sweep.stereo_past_frames, 100.0 * sweep_counts.replaced / std::max(all, 1.0));
    }
    const std::string incidence_title =
        ", static scene, the pixels both cover, by the angle between the ray and the mesh surface's normal";
    if (with_lidar > 0) {
      lidar_tables.Print("Velodyne", with_lidar);
      lidar_incidence.Print("Velodyne" + incidence_title);
      lidar_classes.Print("Velodyne, static scene, by the frame's class of the pixel", source->class_map());
      if (per_frame) {
        std::printf(
            "\nVelodyne, static scene, each frame\n\n"
            "| frame | SGBM RMSE (m) | mesh RMSE (m) | SGBM RMSE 20-40 m (m) | mesh RMSE 20-40 m (m) |\n"
            "|---|---|---|---|---|\n%s",
            frame_rows.c_str());
      }
    }
    if (with_exact > 0) {
      exact_tables.Print("Exact depth", with_exact);
      exact_incidence.Print("Exact depth" + incidence_title);
    }
    if (with_lidar == 0 && with_exact == 0) {
      std::fprintf(stderr, "semap_fusion_table: %s has no frame with a pose and a reference depth\n",
                   sequence.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_fusion_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
