// semap_fusion_table: what fusing the frames gains over any one of them. For each frame of a sequence, the
// SGBM depth map the map is built from (as semap_stereo_bound reads it) and the mesh rendered into the same
// camera are compared with the same reference depths (the Velodyne, and the exact depth of generated
// sequences), per reference-depth bin: RMSE, median |error|, bias (mean error, > 0 = behind the reference)
// and completeness, side by side. Each table is given for every pixel and for the static scene alone: the
// pixels whose class is not a movable one (person, rider, car, truck, bus, train, motorcycle, bicycle), so
// that a map of what stays is not judged by objects that left. The class of a pixel is the frame's own:
// its label image, or with semantics.source: enet the segmenter's labels of the frame (every frame); only
// without either, the label of the mesh triangle hit (which cannot tell a car that left: the mesh shows
// the road behind it there). A third table judges the static scene on the pixels both depth maps cover, so that
// neither is judged on pixels the other leaves out (the mesh covers more, and harder, pixels).
//
// Usage: semap_fusion_table SEQUENCE --mesh MESH.ply [--frames N] [--config FILE] [--set key=value ...]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/eval/mesh_evaluation.h"
#include "bench/sequence_args.h"
#include "engine/depth/stereo_depth.h"
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
const std::vector<double> kEdgesM{0.0, 10.0, 20.0, 30.0, 40.0};
const std::vector<std::string> kMovableClasses{"person", "rider",     "car",    "truck",
                                               "bus",    "train",     "motorcycle", "bicycle"};

// The accumulators of one reference and one pixel selection: per bin and in total, input and mesh.
struct Table {
  explicit Table(const DepthAccuracyOptions& strict) {
    for (int side = 0; side < 2; ++side) {
      total[side].emplace_back(strict);
      for (std::size_t b = 0; b + 1 < kEdgesM.size(); ++b) {
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
      for (auto& b : bins[side]) b.Add(reference, *depth[side]);
    }
  }
  std::vector<DepthAccuracyAccumulator> total[2], bins[2];
};

void PrintRow(const std::string& name, const DepthAccuracy& in, const DepthAccuracy& mesh) {
  std::printf("| %s | %.3f | %.3f | %+.3f | %.1f %% | %.3f | %.3f | %+.3f | %.1f %% | %.2f |\n", name.c_str(), in.rmse_m,
              in.median_abs_m, in.mean_error_m, 100.0 * in.completeness, mesh.rmse_m, mesh.median_abs_m,
              mesh.mean_error_m, 100.0 * mesh.completeness, in.rmse_m > 0.0 ? mesh.rmse_m / in.rmse_m : 0.0);
}

void Print(const std::string& title, const Table& t) {
  std::printf("\n%s\n\n", title.c_str());
  std::printf(
      "| reference depth | SGBM RMSE (m) | SGBM median (m) | SGBM bias (m) | SGBM completeness | mesh RMSE (m) | "
      "mesh median (m) | mesh bias (m) | mesh completeness | mesh / SGBM RMSE |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t b = 0; b < t.bins[0].size(); ++b) {
    char name[32];
    std::snprintf(name, sizeof(name), "%.0f-%.0f m", kEdgesM[b], kEdgesM[b + 1]);
    PrintRow(name, t.bins[0][b].Result(), t.bins[1][b].Result());
  }
  PrintRow("all", t.total[0][0].Result(), t.total[1][0].Result());
}

// `reference` with the pixels of movable classes set to 0 (no reference there).
cv::Mat StaticOnly(const cv::Mat& reference, const cv::Mat& classes, const std::vector<int>& movable) {
  cv::Mat out = reference.clone();
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      if (std::find(movable.begin(), movable.end(), classes.at<int>(v, u)) != movable.end()) out.at<float>(v, u) = 0.0f;
    }
  }
  return out;
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
  explicit ReferenceTables(const DepthAccuracyOptions& strict) : all(strict), static_scene(strict), common(strict) {}
  void Add(const cv::Mat& reference, const cv::Mat& static_reference, const cv::Mat& input, const cv::Mat& mesh) {
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Per-frame SGBM depth against the fused mesh, per reference-depth bin (Velodyne, exact depth)"};
  semap::bench::SequenceArgs args;
  std::string mesh_path;
  args.AddTo(app, "sequence with Velodyne scans or exact depth (KITTI, generated)");
  app.add_option("--mesh", mesh_path, "the mesh of `semap run` on that sequence (.ply or .off)")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    const std::string& sequence = args.sequence;
    const semap::io::FrameSourceOptions input = args.Input(config, true);
    const semap::io::SequenceInfo info = semap::io::DescribeDataset(sequence, input);
    auto source = semap::io::OpenFrameSource(sequence, input);
    std::vector<int> movable;
    for (const std::string& name : kMovableClasses) {
      const int id = source->class_map().FindByName(name);
      if (id >= 0) movable.push_back(id);
    }
    const semap::Mesh mesh = semap::io::ReadMesh(mesh_path);
    const std::vector<int> triangle_labels = semap::TriangleLabels(mesh);
    const semap::StereoDepth depth(config.depth);
    std::unique_ptr<semap::Segmenter> segmenter;
    if (config.semantics.source == semap::LabelSource::kEnet) segmenter = semap::MakeSegmenter(config.semantics);
    const DepthAccuracyOptions strict = config.eval;
    ReferenceTables lidar_tables(strict), exact_tables(strict);
    int with_lidar = 0, with_exact = 0;
    while (auto frame = source->Next()) {
      if (!frame->world_from_cam) continue;
      const auto exact_path = semap::app::ExactDepthPath(info, frame->id);
      if (!frame->velodyne && !exact_path) continue;
      const semap::DisparityResult d = depth.Compute(frame->left, frame->right);
      const cv::Mat stereo = depth.ToDepthView(*frame, d.disparity_px, d.confidence).depth_m;
      const semap::DepthAndTriangles rendered =
          semap::RenderDepthAndTriangles(mesh, frame->calibration, *frame->world_from_cam);
      if (segmenter && frame->labels.empty()) frame->labels = segmenter->Segment(frame->left);
      const cv::Mat classes = semap::PixelClasses(frame->labels, rendered.triangle, triangle_labels);
      if (frame->velodyne) {
        const cv::Mat lidar = semap::LidarDepthImage(*frame->velodyne, frame->calibration, strict);
        lidar_tables.Add(lidar, StaticOnly(lidar, classes, movable), stereo, rendered.depth);
        ++with_lidar;
      }
      if (exact_path) {
        const cv::Mat exact = semap::io::ReadDepthPngMm(*exact_path);
        exact_tables.Add(exact, StaticOnly(exact, classes, movable), stereo, rendered.depth);
        ++with_exact;
      }
    }
    std::printf("Fusion: per-frame SGBM depth (the map's input) against the mesh %s, %s, strict protocol (%s)\n",
                mesh_path.c_str(), sequence.c_str(), semap::ProtocolFilters(strict).c_str());
    if (with_lidar > 0) lidar_tables.Print("Velodyne", with_lidar);
    if (with_exact > 0) exact_tables.Print("Exact depth", with_exact);
    if (with_lidar == 0 && with_exact == 0) {
      std::fprintf(stderr, "semap_fusion_table: %s has no frame with a pose and a reference depth\n", sequence.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_fusion_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
