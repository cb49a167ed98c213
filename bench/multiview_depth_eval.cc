// semap_multiview_depth_eval: plane-sweep depth of every view of a Strecha set that has exact depth
// (`semap synth --layout strecha`: depth/<stem>.png, uint16 mm), against that truth, with the fronto-parallel
// planes only and with the dominant directions found from the labels (DominantDirections on the first
// sweep's depth: the ground's and the walls' RANSAC planes) added. Per view and over all: the share of the
// pixels with a true depth that get a depth, the median and RMSE of |depth − truth| over those, the share
// within 5 cm, and the time of each sweep. Neighbours, resolution and planes as `semap run` sweeps them
// (input.neighbour_views, depth.half_resolution, plane_sweep.*).
//
// Usage: semap_multiview_depth_eval SET [--config FILE] [--set key=value ...]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "bench/stats.h"
#include "engine/depth/dominant_planes.h"
#include "engine/depth/frame_sweep.h"
#include "io/frame_source.h"
#include "io/kitti/ground_truth.h"
#include "io/sfm/strecha.h"

namespace {

using namespace semap;

constexpr double kCloseM = 0.05;  // "within 5 cm"

struct Score {
  std::vector<double> errors_m;  // over the pixels with both a depth and a true depth
  long long with_truth = 0;
  double ms = 0.0;
  void Add(const Score& o) {
    errors_m.insert(errors_m.end(), o.errors_m.begin(), o.errors_m.end());
    with_truth += o.with_truth;
    ms += o.ms;
  }
  void Print(const char* name) const {
    double sq = 0.0;
    long long close = 0;
    for (double e : errors_m) {
      sq += e * e;
      close += e <= kCloseM;
    }
    const double n = static_cast<double>(errors_m.size());
    std::printf(" | %s: valid %.1f %%, median %.3f m, RMSE %.3f m, within 5 cm %.1f %%, %.0f ms", name,
                100.0 * n / std::max<long long>(with_truth, 1), bench::Median(errors_m),
                std::sqrt(sq / std::max(n, 1.0)), 100.0 * close / std::max(n, 1.0), ms);
  }
};

// The sweep's depth at full resolution against the truth.
Score Compare(const PlaneSweepResult& r, const cv::Mat& truth_m, double ms) {
  cv::Mat depth_m;
  cv::resize(r.depth_m, depth_m, truth_m.size(), 0.0, 0.0, cv::INTER_NEAREST);
  Score s;
  s.ms = ms;
  for (int v = 0; v < truth_m.rows; ++v) {
    for (int u = 0; u < truth_m.cols; ++u) {
      const float t = truth_m.at<float>(v, u);
      if (!(t > 0.0f)) continue;
      ++s.with_truth;
      const float z = depth_m.at<float>(v, u);
      if (z > 0.0f) s.errors_m.push_back(std::abs(z - t));
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli("Plane-sweep depth of a generated multi-view set against its exact depth");
  std::string set, config_path;
  std::vector<std::string> overrides;
  cli.add_option("SET", set, "Strecha-layout set with depth/<stem>.png")->required();
  cli.add_option("--config", config_path, "YAML config file");
  cli.add_option("--set", overrides, "section.key=value override (repeatable)");
  CLI11_PARSE(cli, argc, argv);
  try {
    const app::Config config = app::LoadConfig(config_path, overrides);
    io::FrameSourceOptions input = config.input;
    input.layout = io::DatasetLayout::kStrecha;
    const auto files = io::StrechaImageFiles(set);
    auto source = io::OpenFrameSource(set, input);
    const PlaneSweepDepth sweep(config.plane_sweep);
    const double scale = config.depth.half_resolution ? 0.5 : 1.0;
    const ClassMap classes = source->class_map();
    Score all_fronto, all_directions;
    while (auto frame = source->Next()) {
      const cv::Mat truth_m =
          io::ReadDepthPngMm(std::filesystem::path(set) / "depth" /
                             (files.at(static_cast<size_t>(frame->id)).stem().string() + ".png"));
      const PlaneSweepView reference = ReferenceView(*frame, scale);
      std::vector<PlaneSweepView> neighbours;
      for (const CalibratedView& n : frame->neighbour_views) neighbours.push_back(ScaledView(n, scale));
      auto t0 = std::chrono::steady_clock::now();
      const PlaneSweepResult fronto = sweep.Compute(reference, neighbours);
      const double fronto_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const std::vector<SweepDirection> directions =
          DominantDirections(fronto.depth_m, frame->labels, reference, classes);
      t0 = std::chrono::steady_clock::now();
      const PlaneSweepResult with = sweep.Compute(reference, neighbours, directions);
      const double with_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const Score a = Compare(fronto, truth_m, fronto_ms), b = Compare(with, truth_m, with_ms);
      std::printf("view %lld (%zu neighbours, %zu directions)", static_cast<long long>(frame->id),
                  neighbours.size(), directions.size());
      a.Print("fronto-parallel");
      b.Print("with directions");
      std::printf("\n");
      all_fronto.Add(a);
      all_directions.Add(b);
    }
    std::printf("all views");
    all_fronto.Print("fronto-parallel");
    all_directions.Print("with directions");
    std::printf("\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_multiview_depth_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
