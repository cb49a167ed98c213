// semap_pose_epipolar_check: do a sequence's poses agree with its images? A check of the pose reference that
// needs no odometry, no stereo and no depth. Corners of each frame's left image are tracked with pyramidal
// KLT through the next --window frames (and back, to drop mistracks), and each track's Sampson distance to
// the epipolar geometry of the poses' relative motion over the window is measured (engine/eval/
// epipolar_consistency.h):
//   - under the poses as given;
//   - under the poses with a fixed rotation of the camera frame taken out, fitted to the tracks (an extrinsic
//     calibration between the pose source and the camera, or a camera model, off by that rotation);
//   - under each window's own essential matrix (OpenCV's five-point RANSAC on the same tracks): what the
//     tracks themselves allow, the floor of the figure.
// Poses that agree with the images come near the floor; a fixed rotation that brings them there is a frame
// disagreement between the poses and the images, which no odometry run on the images can remove.
//
// --poses FILE checks another trajectory of the same frames instead (KITTI pose format, one line a frame from
// the first frame read: e.g. the odometry's poses_odometry.txt of `semap run --set input.poses=odometry`).
//
// Usage: semap_pose_epipolar_check SEQUENCE [--window N] [--poses FILE] [--frames N] [--config FILE] [--set
// ...]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/grey_image.h"
#include "bench/sequence_args.h"
#include "engine/eval/epipolar_consistency.h"
#include "io/output/trajectory_files.h"

namespace {

// Corners per frame (goodFeaturesToTrack), their quality level and least spacing.
constexpr int kMaxCorners = 2000;
constexpr double kCornerQuality = 0.01;
constexpr double kCornerSpacingPx = 10.0;
// KLT: window, pyramid levels, stop criteria.
constexpr int kKltWindowPx = 21;
constexpr int kKltLevels = 3;
constexpr int kKltMaxIterations = 30;
constexpr double kKltEpsilonPx = 0.01;
// A track is kept when, tracked back through the window, it returns within this of where it started.
constexpr double kRoundTripPx = 0.3;
// Each distance counts at most this much in the mean (a mistrack or a moving object: the cap).
constexpr double kCapPx = 2.0;
// The essential matrix's RANSAC: confidence and inlier threshold.
constexpr double kRansacConfidence = 0.999;
constexpr double kRansacThresholdPx = 0.5;
// A window whose poses move less than this has no epipolar geometry to speak of.
constexpr double kMinBaselineM = 0.5;

// KLT tracks of `start` from image `from` to image `to` (either way), frame by frame; `ok` loses the points
// KLT loses.
std::vector<cv::Point2f> Track(const std::vector<cv::Mat>& images, int from, int to,
                               const std::vector<cv::Point2f>& start, std::vector<unsigned char>* ok) {
  const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations,
                              kKltEpsilonPx);
  std::vector<cv::Point2f> points = start;
  const int step = to > from ? 1 : -1;
  for (int k = from; k != to; k += step) {
    std::vector<cv::Point2f> next;
    std::vector<unsigned char> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(images[static_cast<std::size_t>(k)], images[static_cast<std::size_t>(k + step)],
                             points, next, status, error, cv::Size(kKltWindowPx, kKltWindowPx), kKltLevels,
                             term);
    for (std::size_t i = 0; i < points.size(); ++i) (*ok)[i] = (*ok)[i] && status[i];
    points = std::move(next);
  }
  return points;
}

void Print(const char* what, const semap::EpipolarAgreement& a) {
  std::printf("| %s | %.4f | %.4f |\n", what, a.mean_px, a.median_px);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Whether a sequence's poses agree with its images: epipolar distances of KLT tracks"};
  semap::bench::SequenceArgs args;
  args.AddTo(app, "sequence with poses (KITTI odometry / raw, generated)");
  int window = 10;
  app.add_option("--window", window, "frames a track spans (the relative pose error's window)")
      ->check(CLI::Range(1, 100));
  std::string poses_path;
  app.add_option(
         "--poses", poses_path,
         "check this trajectory (KITTI pose format, a line a frame read) instead of the sequence's poses")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  try {
    const semap::app::Config config = args.LoadConfig();
    auto source = semap::io::OpenFrameSource(args.sequence, args.Input(config, false));
    std::vector<cv::Mat> images;
    std::vector<semap::Pose3d> poses;
    std::optional<semap::StereoCalibration> intrinsics;
    const std::vector<semap::Pose3d> given =
        poses_path.empty() ? std::vector<semap::Pose3d>() : semap::io::ReadKittiPoses(poses_path);
    while (auto frame = source->Next()) {
      if (!poses_path.empty()) {
        if (images.size() >= given.size()) {
          std::fprintf(stderr, "%s: %zu poses, fewer than the sequence's frames read\n", poses_path.c_str(),
                       given.size());
          return 1;
        }
        frame->world_from_cam = given[images.size()];
      }
      if (!frame->world_from_cam) {
        std::fprintf(stderr, "%s: frame %lld has no pose; this check needs the sequence's poses\n",
                     args.sequence.c_str(), static_cast<long long>(frame->id));
        return 1;
      }
      images.push_back(semap::bench::Gray(frame->left));
      poses.push_back(*frame->world_from_cam);
      if (!intrinsics) intrinsics = frame->calibration;
    }
    const std::size_t w = static_cast<std::size_t>(window);
    if (images.size() <= w) {
      std::fprintf(stderr, "%s: %zu frames, a window needs %d + 1\n", args.sequence.c_str(), images.size(),
                   window);
      return 1;
    }
    // The windows with the poses' motions, and the same tracks with each window's own essential matrix.
    std::vector<semap::TrackWindow> windows, own_windows;
    const cv::Mat k = (cv::Mat_<double>(3, 3) << intrinsics->fx_px, 0.0, intrinsics->cx_px, 0.0,
                       intrinsics->fy_px, intrinsics->cy_px, 0.0, 0.0, 1.0);
    for (int i = 0; static_cast<std::size_t>(i) + w < images.size(); ++i) {
      semap::TrackWindow tw;
      tw.b_from_a = poses[static_cast<std::size_t>(i) + w].inverse() * poses[static_cast<std::size_t>(i)];
      if (tw.b_from_a.translation().norm() < kMinBaselineM) continue;
      std::vector<cv::Point2f> start;
      cv::goodFeaturesToTrack(images[static_cast<std::size_t>(i)], start, kMaxCorners, kCornerQuality,
                              kCornerSpacingPx);
      if (start.empty()) continue;
      std::vector<unsigned char> ok(start.size(), 1);
      const std::vector<cv::Point2f> end = Track(images, i, i + window, start, &ok);
      const std::vector<cv::Point2f> back = Track(images, i + window, i, end, &ok);
      std::vector<cv::Point2f> a, b;
      for (std::size_t t = 0; t < start.size(); ++t) {
        if (!ok[t] || std::hypot(back[t].x - start[t].x, back[t].y - start[t].y) > kRoundTripPx) continue;
        a.push_back(start[t]);
        b.push_back(end[t]);
        tw.a_px.emplace_back(start[t].x, start[t].y);
        tw.b_px.emplace_back(end[t].x, end[t].y);
      }
      if (a.size() < 8) continue;
      // The window's own motion (up to scale) from the tracks alone.
      cv::Mat inliers;
      const cv::Mat e =
          cv::findEssentialMat(a, b, k, cv::RANSAC, kRansacConfidence, kRansacThresholdPx, inliers);
      if (e.rows == 3 && e.cols == 3) {
        cv::Mat r, t;
        cv::recoverPose(e, a, b, k, r, t, inliers);
        semap::TrackWindow own = tw;
        for (int row = 0; row < 3; ++row) {
          for (int col = 0; col < 3; ++col) own.b_from_a.linear()(row, col) = r.at<double>(row, col);
          own.b_from_a.translation()[row] = t.at<double>(row);
        }
        own_windows.push_back(std::move(own));
      }
      windows.push_back(std::move(tw));
    }
    if (windows.empty()) {
      std::fprintf(stderr, "%s: no window with tracks and a baseline of %.1f m\n", args.sequence.c_str(),
                   kMinBaselineM);
      return 1;
    }
    const semap::EpipolarAgreement as_given =
        semap::EpipolarAgreementOf(windows, *intrinsics, Eigen::Matrix3d::Identity(), kCapPx);
    const semap::EpipolarRotationFit fit = semap::FitEpipolarRotation(windows, *intrinsics, kCapPx);
    const semap::EpipolarAgreement own =
        semap::EpipolarAgreementOf(own_windows, *intrinsics, Eigen::Matrix3d::Identity(), kCapPx);
    std::printf(
        "%s: %zu windows of %d frames, %d tracks (KLT there and back within %.1f px); Sampson distance "
        "of each track to the epipolar geometry, px (the mean caps each at %.0f px)\n\n",
        args.sequence.c_str(), windows.size(), window, as_given.tracks, kRoundTripPx, kCapPx);
    std::printf("| motion of each window | mean | median |\n|---|---:|---:|\n");
    Print(poses_path.empty() ? "the poses as given" : "the poses of --poses, as given", as_given);
    char label[160];
    std::snprintf(label, sizeof(label), "the poses, camera frame rotated by (%+.3f, %+.3f, %+.3f)° (fitted)",
                  fit.angles_deg.x(), fit.angles_deg.y(), fit.angles_deg.z());
    Print(label, fit.agreement);
    Print("each window's own essential matrix (the tracks' floor)", own);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_pose_epipolar_check: %s\n", e.what());
    return 1;
  }
}
