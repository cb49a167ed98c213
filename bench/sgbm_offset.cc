// semap_sgbm_offset: the disparity offset of the depth stage's own disparities (true = measured + offset),
// found from a sequence's poses alone: a pixel of frame k, at the depth its disparity gives after adding a
// candidate offset, is moved with the poses into frame k + gap, where its disparity must be the one measured
// there plus the same offset. The offset whose residuals have the smallest median |residual| is the one the
// depth maps and the poses agree on. No reference depth is used; where the sequence has a Velodyne, the
// program also prints the median z_sgbm / z_velodyne per depth bin as a check, with and without the offset.
//
// What the map would gain from it: bench/RESULTS.md, "Odometry today" (a fixed +0.2 px on KITTI 04).
//
// Usage: semap_sgbm_offset SEQUENCE [--frames N] [--gap K] [--stride PX] [--config FILE] [--set key=value
// ...]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bench/sequence_args.h"
#include "bench/stats.h"
#include "engine/depth/depth_metrics.h"
#include "engine/depth/stereo_depth.h"

namespace {

// Candidate offsets, px: kMinOffsetPx to kMaxOffsetPx in steps of kOffsetStepPx.
constexpr double kMinOffsetPx = -1.0;
constexpr double kMaxOffsetPx = 1.5;
constexpr double kOffsetStepPx = 0.05;
// A residual beyond this is a mismatch, an occlusion or a moving object, not noise: left out, px.
constexpr double kMaxResidualPx = 2.0;
// Depth bins of the Velodyne check, m.
constexpr double kBinEdgesM[] = {1.0, 10.0, 20.0, 30.0, 40.0};

struct DepthFrame {
  semap::Frame frame;  // images released
  cv::Mat disparity_px;
  cv::Mat confidence;
};

using semap::bench::Median;

// Residuals (disparity in frame b, offset added, minus the one predicted from frame a's pixel) for `offset`.
std::vector<double> Residuals(const DepthFrame& a, const DepthFrame& b, double offset_px, int stride_px) {
  const semap::StereoCalibration& c = a.frame.calibration;
  const semap::Pose3d b_from_a = b.frame.world_from_cam->inverse() * *a.frame.world_from_cam;
  std::vector<double> out;
  for (int v = 0; v < a.disparity_px.rows; v += stride_px) {
    for (int u = 0; u < a.disparity_px.cols; u += stride_px) {
      const float d = a.disparity_px.at<float>(v, u);
      if (!(d > 0.0f) || a.confidence.at<float>(v, u) < 1.0f || d + offset_px <= 0.0) continue;
      const Eigen::Vector3d p = b_from_a * c.Unproject(u, v, c.DepthFromDisparity(d + offset_px));
      if (p.z() <= 0.0) continue;
      const Eigen::Vector2d uv = c.Project(p);
      const int ub = static_cast<int>(std::lround(uv.x())), vb = static_cast<int>(std::lround(uv.y()));
      if (ub < 0 || vb < 0 || ub >= b.disparity_px.cols || vb >= b.disparity_px.rows) continue;
      const float db = b.disparity_px.at<float>(vb, ub);
      if (!(db > 0.0f) || b.confidence.at<float>(vb, ub) < 1.0f) continue;
      const double r = (db + offset_px) - c.DisparityFromDepth(p.z());
      if (std::abs(r) <= kMaxResidualPx) out.push_back(r);
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The depth stage's disparity offset from a sequence's poses (consecutive depth maps)"};
  semap::bench::SequenceArgs args;
  int gap = 1, stride_px = 4;
  args.AddTo(app, "sequence with poses (KITTI raw / odometry, generated)");
  app.add_option("--gap", gap, "frame b is frame a + gap")->check(CLI::PositiveNumber);
  app.add_option("--stride", stride_px, "one pixel in stride x stride of frame a")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    const std::string& sequence = args.sequence;
    const semap::io::FrameSourceOptions input = args.Input(config, config.input.load_velodyne);
    auto source = semap::io::OpenFrameSource(sequence, input);
    const semap::StereoDepth depth(config.depth);
    std::vector<DepthFrame> all;
    while (auto frame = source->Next()) {
      if (!frame->world_from_cam) {
        std::fprintf(stderr, "frame %lld has no pose\n", static_cast<long long>(frame->id));
        return 1;
      }
      const semap::DisparityResult r = depth.Compute(frame->left, frame->right);
      DepthFrame f{*frame, r.disparity_px, r.confidence};
      f.frame.left.release();
      f.frame.right.release();
      all.push_back(std::move(f));
    }
    if (all.size() <= static_cast<size_t>(gap)) {
      std::fprintf(stderr, "fewer than %d frames\n", gap + 1);
      return 1;
    }
    std::printf("%zu frames of %s, pairs (k, k + %d), one pixel in %d x %d\n\n", all.size(), sequence.c_str(),
                gap, stride_px, stride_px);
    std::printf(
        "| offset (px) | residuals | median |residual| (px) | median residual (px) |\n|---|---|---|---|\n");
    double best_offset = 0.0, best_cost = 1e9;
    for (double offset = kMinOffsetPx; offset <= kMaxOffsetPx + 1e-9; offset += kOffsetStepPx) {
      std::vector<double> residuals, abs_residuals;
      for (size_t k = 0; k + static_cast<size_t>(gap) < all.size(); ++k) {
        const std::vector<double> r = Residuals(all[k], all[k + static_cast<size_t>(gap)], offset, stride_px);
        residuals.insert(residuals.end(), r.begin(), r.end());
      }
      for (double r : residuals) abs_residuals.push_back(std::abs(r));
      const double cost = Median(abs_residuals);
      std::printf("| %+.2f | %zu | %.4f | %+.4f |\n", offset, residuals.size(), cost, Median(residuals));
      if (cost < best_cost) best_cost = cost, best_offset = offset;
    }
    std::printf(
        "\nthe depth maps and the poses agree best at an offset of %+.2f px (median |residual| %.4f px)\n",
        best_offset, best_cost);

    // The check against the Velodyne, where there is one: median z_sgbm / z_velodyne per depth bin.
    if (input.load_velodyne) {
      auto check_source = semap::io::OpenFrameSource(sequence, input);
      std::vector<std::vector<double>> ratio_raw(std::size(kBinEdgesM) - 1),
          ratio_corrected(std::size(kBinEdgesM) - 1);
      size_t i = 0;
      while (auto frame = check_source->Next()) {
        if (!frame->velodyne || i >= all.size()) break;
        const DepthFrame& f = all[i++];
        const cv::Mat lidar = semap::LidarDepthImage(*frame->velodyne, frame->calibration, kBinEdgesM[4]);
        for (int v = 0; v < lidar.rows; ++v) {
          for (int u = 0; u < lidar.cols; ++u) {
            const float z_l = lidar.at<float>(v, u), d = f.disparity_px.at<float>(v, u);
            if (!(z_l > 0.0f) || !(d > 0.0f) || f.confidence.at<float>(v, u) < 1.0f) continue;
            for (size_t b = 0; b + 1 < std::size(kBinEdgesM); ++b) {
              if (z_l < kBinEdgesM[b] || z_l >= kBinEdgesM[b + 1]) continue;
              ratio_raw[b].push_back(frame->calibration.DepthFromDisparity(d) / z_l);
              if (d + best_offset > 0.0) {
                ratio_corrected[b].push_back(frame->calibration.DepthFromDisparity(d + best_offset) / z_l);
              }
            }
          }
        }
      }
      if (i > 0) {
        std::printf("\nmedian z_sgbm / z_velodyne (matched pixels), %zu frames\n\n", i);
        std::printf("| depth bin | pixels | no offset | offset %+.2f px |\n|---|---|---|---|\n", best_offset);
        for (size_t b = 0; b + 1 < std::size(kBinEdgesM); ++b) {
          std::printf("| %.0f-%.0f m | %zu | %.4f | %.4f |\n", kBinEdgesM[b], kBinEdgesM[b + 1],
                      ratio_raw[b].size(), Median(ratio_raw[b]), Median(ratio_corrected[b]));
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_sgbm_offset: %s\n", e.what());
    return 1;
  }
  return 0;
}
