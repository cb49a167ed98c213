// semap_depth_eval: quality and speed of the depth stage on ../shared/data/kitti_stereo2015_subset.
// Prints, for the plain OpenCV SGBM reference and for semap's configured depth stage: KITTI D1-all (pixels
// without a disparity count as errors), density, D1 among estimated pixels, point depth errors against the
// Velodyne (median, RMSE of |z − z_lidar| within max_depth_m, camera-frame z on both sides) and the time per
// frame of the depth stage (Compute + ToCloud) on one core (cv::setNumThreads(1)). With --bias, also the
// signed disparity error d − d_gt of matched pixels (confidence 1, |d − d_gt| ≤ 3 px) per ground-truth
// disparity bin: a systematic offset there is a depth bias that grows with range (δz ≈ −z·δd/d).
//
// Usage: semap_depth_eval [--data DIR] [--config FILE] [--set depth.key=value ...] [--no-reference]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "engine/depth/depth_metrics.h"
#include "engine/depth/stereo_depth.h"
#include "tests/common/kitti2015_subset.h"

namespace {

using semap::DepthOptions;

// The reference of the issue: plain OpenCV SGBM 3-way, 128 disparities, block 5, P1 = 8·3·25,
// P2 = 32·3·25, every other parameter at OpenCV's create() default (no uniqueness test, no speckle filter).
DepthOptions PlainSgbmReference(const DepthOptions& base) {
  DepthOptions o = base;
  o.mode = semap::SgbmMode::kThreeWay;
  o.num_disparities = 128;
  o.block_size = 5;
  o.p1 = 8 * 3 * 25;
  o.p2 = 32 * 3 * 25;
  o.uniqueness_ratio = 0;
  o.speckle_window_size = 0;
  o.speckle_range_px = 0;
  o.disp12_max_diff_px = 0;
  o.pre_filter_cap = 0;
  o.half_resolution = false;
  o.fill_max_gap_px = 0;
  o.fill_left_border = false;
  o.min_point_confidence = 1.0f;
  return o;
}

// Signed disparity error of matched pixels per ground-truth disparity bin (bin edges in px, far first).
class SignedBiasTable {
 public:
  void Add(const cv::Mat& disparity_px, const cv::Mat& confidence, const cv::Mat& gt_px) {
    for (int v = 0; v < gt_px.rows; ++v) {
      for (int u = 0; u < gt_px.cols; ++u) {
        const float g = gt_px.at<float>(v, u), d = disparity_px.at<float>(v, u);
        if (g <= 0.0f || d <= 0.0f) continue;
        if (!confidence.empty() && confidence.at<float>(v, u) < 1.0f) continue;
        const double e = double(d) - double(g);
        if (std::abs(e) > kInlierPx) continue;
        for (size_t b = 0; b < kEdgesPx.size(); ++b) {
          const double hi = b + 1 < kEdgesPx.size() ? kEdgesPx[b + 1] : 1e9;
          if (g >= kEdgesPx[b] && g < hi) errors_[b].push_back(e);
        }
      }
    }
  }
  void Print(const std::string& title) {
    std::printf("%s: signed disparity error of matched pixels (|d - d_gt| <= %.0f px), per d_gt bin\n",
                title.c_str(), kInlierPx);
    std::printf("  %-14s %9s %10s %10s %10s\n", "d_gt px", "pixels", "mean px", "median px", "rmse px");
    for (size_t b = 0; b < kEdgesPx.size(); ++b) {
      auto& e = errors_[b];
      if (e.empty()) continue;
      double sum = 0.0, sq = 0.0;
      for (double x : e) sum += x, sq += x * x;
      std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
      const double hi = b + 1 < kEdgesPx.size() ? kEdgesPx[b + 1] : 0.0;
      char range[32];
      if (hi > 0.0)
        std::snprintf(range, sizeof range, "%.0f-%.0f", kEdgesPx[b], hi);
      else
        std::snprintf(range, sizeof range, ">= %.0f", kEdgesPx[b]);
      std::printf("  %-14s %9zu %+10.3f %+10.3f %10.3f\n", range, e.size(), sum / e.size(), e[e.size() / 2],
                  std::sqrt(sq / e.size()));
    }
  }

 private:
  static constexpr double kInlierPx = 3.0;
  // Bins of ground-truth disparity; at KITTI's f·B ≈ 389 px·m: > 39 m, 39–19 m, 19–10 m, 10–5 m, < 5 m.
  static constexpr std::array<double, 5> kEdgesPx{0.0, 10.0, 20.0, 40.0, 80.0};
  std::array<std::vector<double>, kEdgesPx.size()> errors_;
};

void Evaluate(const std::string& title, const DepthOptions& options,
              const std::vector<semap::test::Stereo2015Frame>& frames, bool bias) {
  SignedBiasTable bias_table;
  const semap::StereoDepth depth(options);
  semap::DisparityMetrics total;
  std::vector<double> errors;
  double seconds = 0.0, cpu_seconds = 0.0;
  size_t points = 0;
  for (const auto& f : frames) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const semap::DisparityResult r = depth.Compute(f.frame.left, f.frame.right);
    const semap::LabelledCloud cloud = depth.ToCloud(f.frame, r.disparity_px, r.confidence);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cpu_seconds += double(std::clock() - c0) / CLOCKS_PER_SEC;
    points += cloud.size();
    total += semap::EvaluateDisparity(r.disparity_px, f.gt_disparity_px);
    if (bias) bias_table.Add(r.disparity_px, r.confidence, f.gt_disparity_px);
    if (f.frame.velodyne) {
      const cv::Mat lidar =
          semap::LidarDepthImage(*f.frame.velodyne, f.frame.calibration, options.max_depth_m);
      const auto e =
          semap::DepthErrorsAgainstLidar(cloud, semap::Pose3d::Identity(), lidar, options.max_depth_m);
      errors.insert(errors.end(), e.begin(), e.end());
    }
  }
  const auto stats = semap::SummarizeErrors(errors);
  const double n = static_cast<double>(frames.size());
  std::printf(
      "%-28s D1-all %6.2f %%  density %6.2f %%  D1-est %6.2f %%  | LiDAR: %8zu pts median %.3f m "
      "RMSE %.3f m mean %.3f m | %6.0f pts/frame %7.1f ms/frame wall %7.1f ms CPU\n",
      title.c_str(), 100.0 * total.d1_all(), 100.0 * total.density(), 100.0 * total.d1_estimated(),
      stats.count, stats.median_m, stats.rmse_m, stats.mean_abs_m, points / n, 1000.0 * seconds / n,
      1000.0 * cpu_seconds / n);
  if (bias) bias_table.Print(title);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Depth-stage quality (D1-all, density, LiDAR errors) and speed on the KITTI stereo-2015 subset"};
  std::string data = std::string(SEMAP_SHARED_DIR) + "/data/kitti_stereo2015_subset";
  std::string config_path;
  std::vector<std::string> overrides;
  bool no_reference = false;
  bool half = true;
  bool bias = false;
  int threads = 1;
  app.add_option("--data", data, "kitti_stereo2015_subset folder");
  app.add_option("--config", config_path, "YAML config");
  app.add_option("--set", overrides, "section.key=value overrides");
  app.add_flag("--no-reference", no_reference, "skip the plain OpenCV SGBM reference");
  app.add_option("--half", half, "also evaluate the configured stage at half resolution");
  app.add_flag("--bias", bias, "also print the signed disparity error per ground-truth disparity bin");
  app.add_option("--threads", threads, "OpenCV threads (1 = one core)");
  CLI11_PARSE(app, argc, argv);
  try {
    cv::setNumThreads(threads);
    const semap::app::Config config = semap::app::LoadConfig(config_path, overrides);
    std::vector<semap::test::Stereo2015Frame> frames;
    for (const auto& name : semap::test::ListStereo2015Frames(data)) {
      frames.push_back(semap::test::LoadStereo2015Frame(data, name));
    }
    std::printf("%zu frames from %s, OpenCV threads %d\n", frames.size(), data.c_str(), cv::getNumThreads());
    if (!no_reference)
      Evaluate("plain SGBM 3way (reference)", PlainSgbmReference(config.depth), frames, bias);
    Evaluate("semap depth (config)", config.depth, frames, bias);
    if (half && !config.depth.half_resolution) {
      DepthOptions h = config.depth;
      h.half_resolution = true;
      Evaluate("semap depth, half res", h, frames, bias);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_depth_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
