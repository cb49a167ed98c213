// semap_stereo_bound: how accurate the depth the map is built from is, against the Velodyne, under the same
// two protocols as `semap eval` (strict: every error of every reference depth in eval.min_depth_m to
// eval.max_depth_m; paper: reference depth <= 15 m, |error| <= 2 m). The map's vertices are SGBM points and
// its votes come from the same depth maps, so the strict RMSE of a mesh cannot be expected far below that of
// the depth maps themselves (fusion averages noise only where a surface is seen many times; a surface
// spanning a depth discontinuity adds errors of its own). Prints a markdown table: both protocols, then the
// strict figures by reference distance (the bins of `semap eval`'s breakdown).
//
// The depth map is the one the map receives (StereoDepth::ToDepthView at stride 1: SGBM with semap's filters,
// pixels outside depth.min_depth_m..max_depth_m or below depth.min_point_confidence left empty).
//
// Usage: semap_stereo_bound SEQUENCE [--frames N] [--config FILE] [--set key=value ...]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/sequence_args.h"
#include "engine/depth/stereo_depth.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/eval/error_breakdown.h"

namespace {

using semap::DepthAccuracy;
using semap::DepthAccuracyAccumulator;
using semap::DepthAccuracyOptions;

void PrintRow(const std::string& name, const DepthAccuracy& a) {
  std::printf("| %s | %lld | %.3f | %.3f | %.3f | %.1f %% |\n", name.c_str(),
              static_cast<long long>(a.compared_pixels), a.rmse_m, a.mae_m, a.median_abs_m,
              100.0 * a.completeness);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Accuracy of the SGBM depth maps the map is built from, against the Velodyne (both protocols)"};
  semap::bench::SequenceArgs args;
  args.AddTo(app, "sequence with Velodyne scans (KITTI raw / odometry, generated)");
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    const std::string& sequence = args.sequence;
    auto source = semap::io::OpenFrameSource(sequence, args.Input(config, true));
    const semap::StereoDepth depth(config.depth);
    const DepthAccuracyOptions strict = config.eval;
    const DepthAccuracyOptions paper = semap::PaperProtocol(strict);
    DepthAccuracyAccumulator strict_total(strict), paper_total(paper);
    // The reference-distance bins of `semap eval`'s breakdown, each within the strict depth range.
    const std::vector<double> edges_m = semap::ErrorBreakdownOptions().distance_edges_m;
    std::vector<DepthAccuracyAccumulator> bins;
    for (std::size_t b = 0; b + 1 < edges_m.size(); ++b) {
      DepthAccuracyOptions o = strict;
      o.min_depth_m = std::max(strict.min_depth_m, edges_m[b]);
      o.max_depth_m = std::min(strict.max_depth_m, edges_m[b + 1]);
      bins.emplace_back(o);
    }
    int used = 0;
    while (auto frame = source->Next()) {
      if (!frame->velodyne) continue;
      const semap::DisparityResult d = depth.Compute(frame->left, frame->right);
      // 0 where no point: ToDepthView marks no sky (only the pipeline's labelling does).
      const cv::Mat stereo_depth = depth.ToDepthView(*frame, d.disparity_px, d.confidence).depth_m;
      const cv::Mat lidar = semap::LidarDepthImage(*frame->velodyne, frame->calibration, strict);
      strict_total.Add(lidar, stereo_depth);
      paper_total.Add(lidar, stereo_depth);
      for (auto& b : bins) b.Add(lidar, stereo_depth);
      ++used;
    }
    std::printf("SGBM depth maps (as the map receives them) vs Velodyne, %d frames of %s\n\n", used,
                sequence.c_str());
    std::printf(
        "| protocol | compared px | RMSE (m) | MAE (m) | median (m) | completeness "
        "|\n|---|---|---|---|---|---|\n");
    PrintRow("strict (" + semap::ProtocolFilters(strict) + ")", strict_total.Result());
    PrintRow("paper (" + semap::ProtocolFilters(paper) + ")", paper_total.Result());
    std::printf("\nStrict, by reference distance:\n\n");
    std::printf(
        "| reference depth | compared px | RMSE (m) | MAE (m) | median (m) | completeness "
        "|\n|---|---|---|---|---|---|\n");
    for (std::size_t b = 0; b < bins.size(); ++b) {
      char name[32];
      std::snprintf(name, sizeof(name), "%.0f-%.0f m", edges_m[b], edges_m[b + 1]);
      PrintRow(name, bins[b].Result());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_stereo_bound: %s\n", e.what());
    return 1;
  }
  return 0;
}
