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

constexpr std::size_t kDepthBins = std::size(kBinEdgesM) - 1;
constexpr std::size_t kRadiusBins = std::size(kRadiusEdgesPx) - 1;

// Everything the check measures, summed over the frame pairs.
struct Figures {
  // KLT started at the predicted position (index 0) and at the previous one (1): the error away from the
  // focus of expansion and across it, per depth bin, and along the direction away from the principal point
  // and away from the focus of expansion, per distance from the principal point.
  std::vector<Stats> by_depth[2] = {std::vector<Stats>(kDepthBins), std::vector<Stats>(kDepthBins)};
  std::vector<Stats> by_radius[2] = {std::vector<Stats>(kRadiusBins), std::vector<Stats>(kRadiusBins)};
  // KLT started at the predicted position: the error away from the focus of expansion per depth bin (rows)
  // and distance from the principal point (columns), so that depth and image position are told apart.
  std::vector<std::vector<std::vector<double>>> grid = std::vector<std::vector<std::vector<double>>>(
      kDepthBins, std::vector<std::vector<double>>(kRadiusBins));
  // KLT on frame k's own texture scaled by a known factor about the principal point (the looming of a
  // fronto-parallel surface, exact): the error away from the principal point, per scale.
  std::vector<std::vector<double>> scaled = std::vector<std::vector<double>>(std::size(kScales));
  // The stereo disparity error per start (true disparity, kStereoStartOffPx short) and depth bin.
  std::vector<std::vector<double>> stereo[2] = {std::vector<std::vector<double>>(kDepthBins),
                                                std::vector<std::vector<double>>(kDepthBins)};
};

// KLT as the odometry runs it.
struct Klt {
  cv::Size win;
  cv::TermCriteria term;
  const semap::StereoOdometryOptions& o;
};

// Frame k's corners with a Velodyne return within one pixel: where they are, where the poses move them in
// frame k + 1, and their depth.
struct TrueFlow {
  std::vector<cv::Point2f> start, predicted;
  std::vector<double> depth_m;
};

// The nearest Velodyne depth within one pixel of (u, v) (the first found, rows first); 0 when none.
double DepthNear(const cv::Mat& lidar, int u, int v) {
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= lidar.cols || vv >= lidar.rows) continue;
      const float zl = lidar.at<float>(vv, uu);
      if (zl > 0.0f) return zl;
    }
  }
  return 0.0;
}

TrueFlow CornersWithTrueFlow(const cv::Mat& previous_gray, const cv::Mat& lidar,
                             const semap::Pose3d& b_from_a, const semap::StereoCalibration& c, const Klt& klt,
                             double smooth_share) {
  std::vector<cv::KeyPoint> corners;
  cv::FAST(previous_gray, corners, klt.o.fast_threshold, true);
  TrueFlow flow;
  for (const auto& k : corners) {
    const int u = static_cast<int>(std::lround(k.pt.x)), v = static_cast<int>(std::lround(k.pt.y));
    const double z = DepthNear(lidar, u, v);
    if (z <= 0.0) continue;
    if (smooth_share > 0.0 && !SmoothDepth(lidar, u, v, z, smooth_share)) continue;
    const Eigen::Vector3d p = b_from_a * c.Unproject(k.pt.x, k.pt.y, z);
    if (p.z() <= 0.0) continue;
    const Eigen::Vector2d uv = c.Project(p);
    if (!c.InImage(uv)) continue;
    flow.start.push_back(k.pt);
    flow.predicted.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    flow.depth_m.push_back(z);
  }
  return flow;
}

// KLT from frame k into itself scaled by each of kScales about the principal point, started at the corners'
// old positions: the error along the direction away from the principal point.
void TrackScaledImages(const cv::Mat& previous_gray, const semap::StereoCalibration& c,
                       const std::vector<cv::Point2f>& start, const Klt& klt, Figures* figures) {
  for (size_t si = 0; si < std::size(kScales); ++si) {
    const double sc = kScales[si];
    const cv::Mat a =
        (cv::Mat_<double>(2, 3) << sc, 0.0, c.cx_px * (1.0 - sc), 0.0, sc, c.cy_px * (1.0 - sc));
    cv::Mat warped;
    cv::warpAffine(previous_gray, warped, a, previous_gray.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
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
    cv::calcOpticalFlowPyrLK(previous_gray, warped, from, tracked, status, err, klt.win, klt.o.klt_levels,
                             klt.term, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t i = 0; i < from.size(); ++i) {
      const Eigen::Vector2d e(tracked[i].x - truth[i].x, tracked[i].y - truth[i].y);
      if (!status[i] || e.norm() > kMaxErrorPx) continue;
      const Eigen::Vector2d r(truth[i].x - c.cx_px, truth[i].y - c.cy_px);
      figures->scaled[si].push_back(e.dot(r.normalized()));
    }
  }
}

// The stereo side: the corners matched into frame k's right image as the odometry matches them (pyramidal
// KLT with its stereo levels), started at the true disparity fB/z and kStereoStartOffPx short of it; the
// measured disparity minus the true one, per depth bin.
void MatchStereo(const cv::Mat& previous_gray, const cv::Mat& right_gray, const semap::StereoCalibration& c,
                 const TrueFlow& flow, const Klt& klt, Figures* figures) {
  if (flow.start.empty()) return;
  for (int mode = 0; mode < 2; ++mode) {
    std::vector<cv::Point2f> right(flow.start.size());
    for (size_t i = 0; i < flow.start.size(); ++i) {
      const double d = c.fx_px * c.baseline_m / flow.depth_m[i] - (mode == 0 ? 0.0 : kStereoStartOffPx);
      right[i] = cv::Point2f(flow.start[i].x - static_cast<float>(d), flow.start[i].y);
    }
    std::vector<uchar> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(previous_gray, right_gray, flow.start, right, status, err, klt.win,
                             klt.o.stereo_levels, klt.term, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t i = 0; i < flow.start.size(); ++i) {
      if (!status[i] || std::abs(right[i].y - flow.start[i].y) > klt.o.max_epipolar_error_px) continue;
      const double e = (flow.start[i].x - right[i].x) - c.fx_px * c.baseline_m / flow.depth_m[i];
      const int b = BinOf(kBinEdgesM, flow.depth_m[i]);
      if (std::abs(e) <= kMaxErrorPx && b >= 0) figures->stereo[mode][static_cast<size_t>(b)].push_back(e);
    }
  }
}

// The temporal tracks: KLT from frame k into k + 1 started at the predicted position (mode 0) and at the old
// one (1); the error against the prediction along and across the direction away from the focus of expansion
// `foe`, per depth bin, and by distance from the principal point.
void TrackTemporally(const cv::Mat& previous_gray, const cv::Mat& gray, const semap::StereoCalibration& c,
                     const Eigen::Vector2d& foe, const TrueFlow& flow, const Klt& klt, Figures* figures) {
  if (flow.start.empty()) return;
  for (int mode = 0; mode < 2; ++mode) {
    std::vector<cv::Point2f> tracked = mode == 0 ? flow.predicted : flow.start;
    std::vector<uchar> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(previous_gray, gray, flow.start, tracked, status, err, klt.win, klt.o.klt_levels,
                             klt.term, cv::OPTFLOW_USE_INITIAL_FLOW);
    std::vector<Stats>& stats = figures->by_depth[mode];
    std::vector<Stats>& by_radius = figures->by_radius[mode];
    for (size_t i = 0; i < flow.start.size(); ++i) {
      if (!status[i]) continue;
      const cv::Point2f& predicted = flow.predicted[i];
      const Eigen::Vector2d e(tracked[i].x - predicted.x, tracked[i].y - predicted.y);
      if (e.norm() > kMaxErrorPx) continue;
      const Eigen::Vector2d r(predicted.x - foe.x(), predicted.y - foe.y());
      if (r.norm() < kMinRadiusPx) continue;
      const Eigen::Vector2d radial = r.normalized();
      // By distance from the principal point: the error along that direction (a lens distortion left in the
      // rectified images would stretch or shrink the flow there).
      const Eigen::Vector2d from_centre(predicted.x - c.cx_px, predicted.y - c.cy_px);
      const double rc = from_centre.norm();
      const int rb = rc > 0.0 ? BinOf(kRadiusEdgesPx, rc) : -1;
      const int zb = BinOf(kBinEdgesM, flow.depth_m[i]);
      if (rb >= 0) {
        by_radius[static_cast<size_t>(rb)].radial.push_back(e.dot(from_centre / rc));
        by_radius[static_cast<size_t>(rb)].tangential.push_back(e.dot(radial));
        if (mode == 0 && zb >= 0)
          figures->grid[static_cast<size_t>(zb)][static_cast<size_t>(rb)].push_back(e.dot(radial));
      }
      if (zb >= 0) {
        stats[static_cast<size_t>(zb)].radial.push_back(e.dot(radial));
        stats[static_cast<size_t>(zb)].tangential.push_back(radial.x() * e.y() - radial.y() * e.x());
      }
    }
  }
}

// One pair of consecutive frames (the previous one with a Velodyne scan, both with poses) into the figures;
// false, with nothing added, when the camera does not move forwards (no focus of expansion ahead): such a
// pair does not count towards kScaleEveryFrames.
bool AddFramePair(const semap::Frame& previous, const cv::Mat& previous_gray, const semap::Frame& frame,
                  const cv::Mat& gray, int frame_index, const Klt& klt, double smooth_share,
                  Figures* figures) {
  const semap::StereoCalibration& c = frame.calibration;
  const cv::Mat lidar = semap::LidarDepthImage(*previous.velodyne, c, kMaxDepthM);
  const semap::Pose3d b_from_a = frame.world_from_cam->inverse() * *previous.world_from_cam;
  // The focus of expansion: the image of the motion's direction in frame k + 1, from frame k's camera centre
  // (b_from_a's translation, in b's coordinates) to b's.
  const Eigen::Vector3d direction_b = -b_from_a.translation();
  if (direction_b.z() <= 0.0) return false;
  const Eigen::Vector2d foe = c.Project(direction_b);
  const TrueFlow flow = CornersWithTrueFlow(previous_gray, lidar, b_from_a, c, klt, smooth_share);
  if (frame_index % kScaleEveryFrames == 1) TrackScaledImages(previous_gray, c, flow.start, klt, figures);
  MatchStereo(previous_gray, Gray(previous.right), c, flow, klt, figures);
  TrackTemporally(previous_gray, gray, c, foe, flow, klt, figures);
  return true;
}

const char* TemporalStart(int mode) { return mode == 0 ? "the predicted position" : "the previous position"; }

void PrintFigures(const std::string& sequence, const semap::StereoOdometryOptions& o, const Figures& f) {
  std::printf("KLT tracks (window %d px, %d levels) minus the flow of the poses and the Velodyne, %s\n\n",
              o.klt_window_px, o.klt_levels, sequence.c_str());
  std::printf(
      "| KLT started at | depth | tracks | radial mean (px) | radial median (px) | across mean (px) |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (int mode = 0; mode < 2; ++mode) {
    const std::vector<Stats>& stats = f.by_depth[mode];
    for (size_t b = 0; b + 1 < std::size(kBinEdgesM); ++b) {
      std::printf("| %s | %.0f-%.0f m | %zu | %+.4f | %+.4f | %+.4f |\n", TemporalStart(mode), kBinEdgesM[b],
                  kBinEdgesM[b + 1], stats[b].radial.size(), Mean(stats[b].radial), Median(stats[b].radial),
                  Mean(stats[b].tangential));
    }
  }
  std::printf(
      "\n| KLT started at | distance from the principal point | tracks | mean along it (px) | median along "
      "it "
      "(px) | mean away from the focus of expansion (px) |\n|---|---|---|---|---|---|\n");
  for (int mode = 0; mode < 2; ++mode) {
    const std::vector<Stats>& stats = f.by_radius[mode];
    for (size_t b = 0; b + 1 < std::size(kRadiusEdgesPx); ++b) {
      std::printf("| %s | %.0f-%.0f px | %zu | %+.4f | %+.4f | %+.4f |\n", TemporalStart(mode),
                  kRadiusEdgesPx[b], kRadiusEdgesPx[b + 1], stats[b].radial.size(), Mean(stats[b].radial),
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
                  f.stereo[mode][b].size(), Mean(f.stereo[mode][b]), Median(f.stereo[mode][b]));
    }
  }
  std::printf(
      "\nKLT on frame k's own image scaled by a known factor about the principal point (every %d frames, "
      "started at the corner's old position): error away from the principal point\n\n| scale | tracks | "
      "mean (px) | median (px) |\n|---|---|---|---|\n",
      kScaleEveryFrames);
  for (size_t si = 0; si < std::size(kScales); ++si) {
    std::printf("| %.2f | %zu | %+.4f | %+.4f |\n", kScales[si], f.scaled[si].size(), Mean(f.scaled[si]),
                Median(f.scaled[si]));
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
    for (const auto& cell : f.grid[z]) std::printf(" %+.3f (%zu) |", Median(cell), cell.size());
    std::printf("\n");
  }
}

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
    auto source = semap::io::OpenFrameSource(args.sequence, args.Input(config, true));
    const semap::StereoOdometryOptions& o = config.odometry;
    const Klt klt{
        cv::Size(o.klt_window_px, o.klt_window_px),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations, kKltEpsilonPx),
        o};
    Figures figures;
    std::optional<semap::Frame> previous;
    cv::Mat previous_gray;
    int frame_index = 0;
    while (auto frame = source->Next()) {
      const cv::Mat gray = Gray(frame->left);
      bool counted = true;
      if (previous && previous->velodyne && previous->world_from_cam && frame->world_from_cam) {
        counted =
            AddFramePair(*previous, previous_gray, *frame, gray, frame_index, klt, smooth_share, &figures);
      }
      previous = std::move(*frame);
      previous_gray = gray;
      if (counted) ++frame_index;
    }
    PrintFigures(args.sequence, o, figures);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_flow_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
