// semap_flow_check: are the odometry's temporal feature tracks biased? For each pair of consecutive frames of
// a sequence with poses and a Velodyne, FAST corners of frame k that have a Velodyne return within one pixel
// are moved with the poses into frame k + 1 (the true flow, from the scanner's depth), and tracked there with
// the odometry's pyramidal KLT (its window, levels and stop criteria, started where the true flow puts them
// and, separately, where they were). The difference tracked − predicted is split into its component along the
// direction away from the focus of expansion (radial: a positive mean lengthens every step of a
// forward-moving camera) and across it, per depth bin; and by distance from the principal point, along the
// direction away from it (where a lens distortion left in the rectified images would show); and the two
// crossed. The stereo side too: the same corners matched into frame k's right image with the odometry's
// stereo KLT, their disparity against fB/z of the Velodyne, per depth bin. --smooth keeps only corners away
// from depth edges.
//
// Usage: semap_flow_check SEQUENCE [--frames N] [--smooth SHARE] [--config FILE] [--set key=value ...]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/grey_image.h"
#include "bench/sequence_args.h"
#include "bench/stats.h"
#include "engine/depth/depth_metrics.h"

namespace {

using semap::bench::BinOf;
using semap::bench::Gray;
using semap::bench::Mean;
using semap::bench::Median;

// KLT's stop criteria, as in engine/odometry.
constexpr int kKltMaxIterations = 30;
constexpr double kKltEpsilonPx = 0.01;
// Depth bins, m, and the farthest Velodyne depth used.
constexpr double kBinEdgesM[] = {1.0, 10.0, 20.0, 40.0};
constexpr double kMaxDepthM = 40.0;
// Bins of the distance from the principal point, px.
constexpr double kRadiusEdgesPx[] = {0.0, 150.0, 300.0, 450.0, 600.0, 800.0};
// A tracked point farther than this from its prediction is a mistrack (left out), px.
constexpr double kMaxErrorPx = 3.0;
// The known scalings of frame k's image (a surface at depth Z approached by t: Z / (Z - t)), and every how
// many frames they are tried.
constexpr double kScales[] = {1.02, 1.05, 1.10};
constexpr int kScaleEveryFrames = 5;
// The second start of the stereo match: this much short of the true disparity, px.
constexpr double kStereoStartOffPx = 2.0;
// Corners closer than this to the focus of expansion have no radial direction, px.
constexpr double kMinRadiusPx = 20.0;

// True when every Velodyne return within kSmoothRadiusPx of (u, v), and at least kMinSmoothReturns of
// them, lie within `share` of depth `z_m`.
constexpr int kSmoothRadiusPx = 3;
constexpr int kMinSmoothReturns = 3;
bool SmoothDepth(const cv::Mat& lidar, int u, int v, double z_m, double share) {
  int returns = 0;
  for (int dv = -kSmoothRadiusPx; dv <= kSmoothRadiusPx; ++dv) {
    for (int du = -kSmoothRadiusPx; du <= kSmoothRadiusPx; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= lidar.cols || vv >= lidar.rows) continue;
      const float zl = lidar.at<float>(vv, uu);
      if (zl <= 0.0f) continue;
      if (std::abs(zl - z_m) > share * z_m) return false;
      ++returns;
    }
  }
  return returns >= kMinSmoothReturns;
}

struct Stats {
  std::vector<double> radial, tangential;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Bias of the odometry's temporal KLT tracks against the flow the poses and the Velodyne predict"};
  semap::bench::SequenceArgs args;
  args.AddTo(app, "sequence with poses and Velodyne (KITTI odometry / raw)");
  double smooth_share = 0.0;
  app.add_option(
         "--smooth", smooth_share,
         "keep only corners whose Velodyne returns within 3 px all lie within this share of their depth "
         "(e.g. 0.02: no depth edge, where the scanner, mounted apart from the camera, may see another "
         "surface than the camera); 0 = every corner")
      ->check(CLI::Range(0.0, 1.0));
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    const std::string& sequence = args.sequence;
    auto source = semap::io::OpenFrameSource(sequence, args.Input(config, true));
    const semap::StereoOdometryOptions& o = config.odometry;
    const cv::Size win(o.klt_window_px, o.klt_window_px);
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations,
                                kKltEpsilonPx);
    std::vector<Stats> from_truth(std::size(kBinEdgesM) - 1), from_start(std::size(kBinEdgesM) - 1);
    std::vector<Stats> radius_truth(std::size(kRadiusEdgesPx) - 1),
        radius_start(std::size(kRadiusEdgesPx) - 1);
    // KLT started at the predicted position: the error away from the focus of expansion per depth bin (rows)
    // and distance from the principal point (columns), so that depth and image position are told apart.
    std::vector<std::vector<std::vector<double>>> grid(
        std::size(kBinEdgesM) - 1, std::vector<std::vector<double>>(std::size(kRadiusEdgesPx) - 1));
    std::optional<semap::Frame> previous;
    cv::Mat previous_gray;
    // KLT on frame k's own texture scaled by a known factor about the principal point (the looming of a
    // fronto-parallel surface, exact): the error away from the principal point, per scale.
    std::vector<std::vector<double>> scaled(std::size(kScales));
    int frame_index = 0;
    // The stereo disparity error per start (true disparity, kStereoStartOffPx short) and depth bin.
    std::vector<std::vector<double>> stereo[2] = {
        std::vector<std::vector<double>>(std::size(kBinEdgesM) - 1),
        std::vector<std::vector<double>>(std::size(kBinEdgesM) - 1)};
    while (auto frame = source->Next()) {
      const cv::Mat gray = Gray(frame->left);
      if (previous && previous->velodyne && previous->world_from_cam && frame->world_from_cam) {
        const semap::StereoCalibration& c = frame->calibration;
        const cv::Mat lidar = semap::LidarDepthImage(*previous->velodyne, c, kMaxDepthM);
        const semap::Pose3d b_from_a = frame->world_from_cam->inverse() * *previous->world_from_cam;
        // The focus of expansion: the image of the motion's direction in frame k + 1, from frame k's camera
        // centre (b_from_a's translation, in b's coordinates) to b's.
        const Eigen::Vector3d direction_b = -b_from_a.translation();
        if (direction_b.z() <= 0.0) {
          previous = std::move(*frame);
          previous_gray = gray;
          continue;
        }
        const Eigen::Vector2d foe = c.Project(direction_b);
        std::vector<cv::KeyPoint> corners;
        cv::FAST(previous_gray, corners, o.fast_threshold, true);
        std::vector<cv::Point2f> start, predicted;
        std::vector<double> depth_m;
        for (const auto& k : corners) {
          const int u = static_cast<int>(std::lround(k.pt.x)), v = static_cast<int>(std::lround(k.pt.y));
          double z = 0.0;  // the nearest Velodyne depth within one pixel
          for (int dv = -1; dv <= 1 && z == 0.0; ++dv) {
            for (int du = -1; du <= 1; ++du) {
              const int uu = u + du, vv = v + dv;
              if (uu < 0 || vv < 0 || uu >= lidar.cols || vv >= lidar.rows) continue;
              const float zl = lidar.at<float>(vv, uu);
              if (zl > 0.0f) {
                z = zl;
                break;
              }
            }
          }
          if (z <= 0.0) continue;
          if (smooth_share > 0.0 && !SmoothDepth(lidar, u, v, z, smooth_share)) continue;
          const Eigen::Vector3d p = b_from_a * c.Unproject(k.pt.x, k.pt.y, z);
          if (p.z() <= 0.0) continue;
          const Eigen::Vector2d uv = c.Project(p);
          if (!c.InImage(uv)) continue;
          start.push_back(k.pt);
          predicted.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
          depth_m.push_back(z);
        }
        if (frame_index % kScaleEveryFrames == 1) {
          for (size_t si = 0; si < std::size(kScales); ++si) {
            const double sc = kScales[si];
            const cv::Mat a =
                (cv::Mat_<double>(2, 3) << sc, 0.0, c.cx_px * (1.0 - sc), 0.0, sc, c.cy_px * (1.0 - sc));
            cv::Mat warped;
            cv::warpAffine(previous_gray, warped, a, previous_gray.size(), cv::INTER_CUBIC,
                           cv::BORDER_REFLECT);
            std::vector<cv::Point2f> from, truth;
            for (const auto& p : start) {
              const cv::Point2f q(static_cast<float>(c.cx_px + sc * (p.x - c.cx_px)),
                                  static_cast<float>(c.cy_px + sc * (p.y - c.cy_px)));
              const double r = std::hypot(q.x - c.cx_px, q.y - c.cy_px);
              if (r < kMinRadiusPx || q.x < 0.0f || q.y < 0.0f || q.x >= static_cast<float>(warped.cols) ||
                  q.y >= static_cast<float>(warped.rows)) {
                continue;
              }
              from.push_back(p);
              truth.push_back(q);
            }
            if (from.empty()) continue;
            std::vector<cv::Point2f> tracked = from;
            std::vector<uchar> status;
            std::vector<float> err;
            cv::calcOpticalFlowPyrLK(previous_gray, warped, from, tracked, status, err, win, o.klt_levels,
                                     term, cv::OPTFLOW_USE_INITIAL_FLOW);
            for (size_t i = 0; i < from.size(); ++i) {
              const Eigen::Vector2d e(tracked[i].x - truth[i].x, tracked[i].y - truth[i].y);
              if (!status[i] || e.norm() > kMaxErrorPx) continue;
              const Eigen::Vector2d r(truth[i].x - c.cx_px, truth[i].y - c.cy_px);
              scaled[si].push_back(e.dot(r.normalized()));
            }
          }
        }
        // The stereo side: the corners matched into frame k's right image as the odometry matches them
        // (pyramidal KLT with its stereo levels), started at the true disparity fB/z and kStereoStartOffPx
        // short of it; the measured disparity minus the true one, per depth bin.
        {
          const cv::Mat right_gray = Gray(previous->right);
          for (int mode = 0; mode < 2; ++mode) {
            std::vector<cv::Point2f> right(start.size());
            for (size_t i = 0; i < start.size(); ++i) {
              const double d = c.fx_px * c.baseline_m / depth_m[i] - (mode == 0 ? 0.0 : kStereoStartOffPx);
              right[i] = cv::Point2f(start[i].x - static_cast<float>(d), start[i].y);
            }
            std::vector<uchar> status;
            std::vector<float> err;
            if (start.empty()) break;
            cv::calcOpticalFlowPyrLK(previous_gray, right_gray, start, right, status, err, win,
                                     o.stereo_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
            for (size_t i = 0; i < start.size(); ++i) {
              if (!status[i] || std::abs(right[i].y - start[i].y) > o.max_epipolar_error_px) continue;
              const double e = (start[i].x - right[i].x) - c.fx_px * c.baseline_m / depth_m[i];
              const int b = BinOf(kBinEdgesM, depth_m[i]);
              if (std::abs(e) <= kMaxErrorPx && b >= 0) stereo[mode][static_cast<size_t>(b)].push_back(e);
            }
          }
        }
        for (int mode = 0; mode < 2; ++mode) {
          std::vector<cv::Point2f> tracked = mode == 0 ? predicted : start;
          std::vector<uchar> status;
          std::vector<float> err;
          if (start.empty()) break;
          cv::calcOpticalFlowPyrLK(previous_gray, gray, start, tracked, status, err, win, o.klt_levels, term,
                                   cv::OPTFLOW_USE_INITIAL_FLOW);
          std::vector<Stats>& stats = mode == 0 ? from_truth : from_start;
          std::vector<Stats>& by_radius = mode == 0 ? radius_truth : radius_start;
          for (size_t i = 0; i < start.size(); ++i) {
            if (!status[i]) continue;
            const Eigen::Vector2d e(tracked[i].x - predicted[i].x, tracked[i].y - predicted[i].y);
            if (e.norm() > kMaxErrorPx) continue;
            const Eigen::Vector2d r(predicted[i].x - foe.x(), predicted[i].y - foe.y());
            if (r.norm() < kMinRadiusPx) continue;
            const Eigen::Vector2d radial = r.normalized();
            // By distance from the principal point: the error along that direction (a lens distortion left
            // in the rectified images would stretch or shrink the flow there).
            const Eigen::Vector2d from_centre(predicted[i].x - c.cx_px, predicted[i].y - c.cy_px);
            const double rc = from_centre.norm();
            const int rb = rc > 0.0 ? BinOf(kRadiusEdgesPx, rc) : -1;
            const int zb = BinOf(kBinEdgesM, depth_m[i]);
            if (rb >= 0) {
              by_radius[static_cast<size_t>(rb)].radial.push_back(e.dot(from_centre / rc));
              by_radius[static_cast<size_t>(rb)].tangential.push_back(e.dot(radial));
              if (mode == 0 && zb >= 0)
                grid[static_cast<size_t>(zb)][static_cast<size_t>(rb)].push_back(e.dot(radial));
            }
            if (zb >= 0) {
              stats[static_cast<size_t>(zb)].radial.push_back(e.dot(radial));
              stats[static_cast<size_t>(zb)].tangential.push_back(radial.x() * e.y() - radial.y() * e.x());
            }
          }
        }
      }
      previous = std::move(*frame);
      previous_gray = gray;
      ++frame_index;
    }
    std::printf("KLT tracks (window %d px, %d levels) minus the flow of the poses and the Velodyne, %s\n\n",
                o.klt_window_px, o.klt_levels, sequence.c_str());
    std::printf(
        "| KLT started at | depth | tracks | radial mean (px) | radial median (px) | across mean (px) |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (int mode = 0; mode < 2; ++mode) {
      const std::vector<Stats>& stats = mode == 0 ? from_truth : from_start;
      for (size_t b = 0; b + 1 < std::size(kBinEdgesM); ++b) {
        std::printf("| %s | %.0f-%.0f m | %zu | %+.4f | %+.4f | %+.4f |\n",
                    mode == 0 ? "the predicted position" : "the previous position", kBinEdgesM[b],
                    kBinEdgesM[b + 1], stats[b].radial.size(), Mean(stats[b].radial), Median(stats[b].radial),
                    Mean(stats[b].tangential));
      }
    }
    std::printf(
        "\n| KLT started at | distance from the principal point | tracks | mean along it (px) | median along "
        "it "
        "(px) | mean away from the focus of expansion (px) |\n|---|---|---|---|---|---|\n");
    for (int mode = 0; mode < 2; ++mode) {
      const std::vector<Stats>& stats = mode == 0 ? radius_truth : radius_start;
      for (size_t b = 0; b + 1 < std::size(kRadiusEdgesPx); ++b) {
        std::printf("| %s | %.0f-%.0f px | %zu | %+.4f | %+.4f | %+.4f |\n",
                    mode == 0 ? "the predicted position" : "the previous position", kRadiusEdgesPx[b],
                    kRadiusEdgesPx[b + 1], stats[b].radial.size(), Mean(stats[b].radial),
                    Median(stats[b].radial), Mean(stats[b].tangential));
      }
    }
    std::printf(
        "\nStereo: KLT disparity (left to right, %d levels) minus fB/z of the Velodyne\n\n| KLT started at | "
        "depth | matches | mean (px) | median (px) |\n|---|---|---|---|---|\n",
        o.stereo_levels);
    for (int mode = 0; mode < 2; ++mode) {
      for (size_t b = 0; b + 1 < std::size(kBinEdgesM); ++b) {
        std::printf("| %s | %.0f-%.0f m | %zu | %+.4f | %+.4f |\n",
                    mode == 0 ? "the true disparity" : "2 px short of it", kBinEdgesM[b], kBinEdgesM[b + 1],
                    stereo[mode][b].size(), Mean(stereo[mode][b]), Median(stereo[mode][b]));
      }
    }
    std::printf(
        "\nKLT on frame k's own image scaled by a known factor about the principal point (every %d frames, "
        "started at the corner's old position): error away from the principal point\n\n| scale | tracks | "
        "mean (px) | median (px) |\n|---|---|---|---|\n",
        kScaleEveryFrames);
    for (size_t si = 0; si < std::size(kScales); ++si) {
      std::printf("| %.2f | %zu | %+.4f | %+.4f |\n", kScales[si], scaled[si].size(), Mean(scaled[si]),
                  Median(scaled[si]));
    }
    std::printf(
        "\nKLT started at the predicted position: median error away from the focus of expansion (px, "
        "tracks), by depth and distance from the principal point\n\n| depth |");
    for (size_t b = 0; b + 1 < std::size(kRadiusEdgesPx); ++b) {
      std::printf(" %.0f-%.0f px |", kRadiusEdgesPx[b], kRadiusEdgesPx[b + 1]);
    }
    std::printf("\n|---|");
    for (size_t b = 0; b + 1 < std::size(kRadiusEdgesPx); ++b) std::printf("---|");
    std::printf("\n");
    for (size_t z = 0; z + 1 < std::size(kBinEdgesM); ++z) {
      std::printf("| %.0f-%.0f m |", kBinEdgesM[z], kBinEdgesM[z + 1]);
      for (const auto& cell : grid[z]) std::printf(" %+.3f (%zu) |", Median(cell), cell.size());
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_flow_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
