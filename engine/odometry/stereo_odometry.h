// Stereo visual odometry: the left camera's pose from a stream of rectified stereo pairs, for sequences
// that come without poses (see engine/odometry/README.md for the scheme and why it was chosen).
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/options.h"

namespace semap {

// Which terms of the rig's disparity offset the odometry estimates from the stream (DisparityOffset).
enum class OffsetEstimate { kOff, kConstant, kPerRow };

struct StereoOdometryOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  int max_features = 500;
  int grid_cols = 12;
  int grid_rows = 4;
  int fast_threshold = 15;
  int klt_window_px = 11;
  int klt_levels = 3;
  int stereo_levels = 5;
  double max_epipolar_error_px = 1.0;
  double max_stereo_check_px = 0.75;
  double min_disparity_px = 1.0;
  double ransac_threshold_px = 2.0;
  int ransac_iterations = 150;
  double inlier_threshold_px = 1.5;
  int min_inliers = 40;
  double min_inlier_ratio = 0.2;
  double max_speed_mps = 50.0;
  double max_rotation_rate_deg_s = 120.0;
  int max_bridged_frames = 3;
  int keyframe_max_frames = 3;
  double keyframe_min_inlier_ratio = 0.6;
  double disparity_offset_px = 0.0;
  double disparity_offset_per_row_px = 0.0;
  OffsetEstimate estimate_disparity_offset = OffsetEstimate::kOff;
  bool offset_in_depth = false;

  // A disparity offset (either term) beyond this is not a rectification error but a wrong calibration, px.
  static constexpr double kMaxDisparityOffsetPx = 5.0;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("max_features", &max_features,
            "features kept per frame (tracked ones first, then new FAST corners in the emptiest grid cells)",
            AtLeast(8));
    v.Field("grid_cols", &grid_cols, "columns of the grid that spreads the features over the image",
            AtLeast(1));
    v.Field("grid_rows", &grid_rows, "rows of that grid", AtLeast(1));
    v.Field("fast_threshold", &fast_threshold, "FAST corner threshold (grey levels)", In(1, 255));
    v.Field("klt_window_px", &klt_window_px, "pyramidal KLT window side, px", AtLeast(5).Odd());
    v.Field("klt_levels", &klt_levels, "KLT pyramid levels above full resolution for tracking between frames",
            In(0, 8));
    v.Field("stereo_levels", &stereo_levels,
            "KLT pyramid levels for left-to-right matching (reaches disparities of about window x 2^levels)",
            In(0, 8));
    v.Field("max_epipolar_error_px", &max_epipolar_error_px,
            "a stereo match may leave the left point's row by this much, px (rectified images)", Above(0));
    v.Field("max_stereo_check_px", &max_stereo_check_px,
            "left -> right -> left round trip of a stereo match must land this close to the start, px",
            Above(0));
    v.Field("min_disparity_px", &min_disparity_px,
            "stereo matches below this disparity are not triangulated, px", Above(0));
    v.Field("ransac_threshold_px", &ransac_threshold_px, "P3P RANSAC inlier reprojection error, px",
            Above(0));
    v.Field("ransac_iterations", &ransac_iterations, "P3P RANSAC iterations", AtLeast(1));
    v.Field("inlier_threshold_px", &inlier_threshold_px,
            "after refinement, a track is an inlier when its stereo reprojection error is below this, px",
            Above(0));
    v.Field("min_inliers", &min_inliers, "fewer inliers than this: tracking failed on the frame", AtLeast(6));
    v.Field("min_inlier_ratio", &min_inlier_ratio,
            "inliers below this fraction of the tracked features: tracking failed on the frame", In(0, 1));
    v.Field("max_speed_mps", &max_speed_mps, "a motion faster than this is a jump: tracking failed, m/s",
            Above(0));
    v.Field("max_rotation_rate_deg_s", &max_rotation_rate_deg_s,
            "a rotation faster than this is a jump: tracking failed, deg/s", Above(0));
    v.Field(
        "max_bridged_frames", &max_bridged_frames,
        "failed frames in a row bridged from the last tracked one before tracking restarts on the current "
        "frame",
        AtLeast(0));
    v.Field("keyframe_max_frames", &keyframe_max_frames,
            "frames tracked from one reference (keyframe) before the last of them becomes the next: fewer "
            "estimates chained per metre, so less drift (1 = every frame is the next one's reference)",
            AtLeast(1));
    v.Field("keyframe_min_inlier_ratio", &keyframe_min_inlier_ratio,
            "a tracked frame becomes the reference at once when fewer than this share of the reference's "
            "features are inliers (the view has moved on)",
            In(0, 1));
    v.Field(
        "disparity_offset_px", &disparity_offset_px,
        "added to every measured disparity (true = measured + offset) in the odometry, and with "
        "offset_in_depth in the depth of the frames it reads: a rectification off by a fraction of a pixel "
        "scales every step; the start of the estimate when estimate_disparity_offset, px",
        In(-kMaxDisparityOffsetPx, kMaxDisparityOffsetPx));
    v.Field("disparity_offset_per_row_px", &disparity_offset_per_row_px,
            "a second term of that offset, growing with the image row: offset = disparity_offset_px + this x "
            "(v - cy) / fy (a roll between the cameras); the start of its estimate when "
            "estimate_disparity_offset is per_row, px",
            In(-kMaxDisparityOffsetPx, kMaxDisparityOffsetPx));
    v.Enum("estimate_disparity_offset", &estimate_disparity_offset,
           {{"off", OffsetEstimate::kOff},
            {"constant", OffsetEstimate::kConstant},
            {"per_row", OffsetEstimate::kPerRow}},
           "estimate the offset from the stream (each tracked frame's depths against its motion, averaged by "
           "their information) and use it from the next frame on: off, its constant, or its constant and "
           "per-row term; off by default (docs/odometry.md says when it pays)");
    v.Field(
        "offset_in_depth", &offset_in_depth,
        "the depth of the frames the odometry reads (SGBM's disparities: the map's points and votes) uses "
        "the odometry's offset too; off by default: the offset the odometry finds is that of its own feature "
        "matches, and SGBM's can differ (KITTI 04: +0.28 against +0.05 to +0.10 px)");
  }

  void Check() const;
};

// How a frame's pose was found.
enum class OdometryStatus {
  kFirst,      // the first frame: the pose it was given (the identity by default)
  kTracked,    // estimated from the features tracked from the reference frame
  kBridged,    // tracking failed: constant-velocity guess from the last tracked frame
  kRestarted,  // tracking restarted on this frame after failing: its pose is a constant-velocity guess
};

const char* OdometryStatusName(OdometryStatus status);

struct OdometryResult {
  Pose3d world_from_cam = Pose3d::Identity();
  OdometryStatus status = OdometryStatus::kFirst;
  int features = 0;         // reference features tracked into this frame
  int inliers = 0;          // of those, consistent with the estimated motion
  int stereo_features = 0;  // features with a stereo match that the next frame is tracked from (0: failed)
  bool keyframe = false;    // this frame became the reference (the first frame, a restart, or see keyframe_*)
  double cpu_ms = 0.0;      // CPU time of this Track() call (the calling thread's)
  DisparityOffset disparity_offset;  // the disparity offset used for this frame
  // This frame's own estimate of the offset and the standard deviation of its constant
  // (estimate_disparity_offset, tracked frames that voted; else zero), px.
  DisparityOffset frame_offset;
  double frame_offset_sigma_px = 0.0;
  std::string problem;  // why tracking failed (kBridged, kRestarted); empty otherwise
};

// Keyframe-to-frame stereo odometry. Each frame: the reference frame's features (FAST corners with a stereo
// match) are tracked into the left image (pyramidal KLT from a constant-velocity prediction), matched into
// the right one, the motion comes from P3P RANSAC and a robust Gauss-Newton refinement of the stereo
// reprojection error in both frames. Every keyframe_max_frames tracked frames (sooner when the reference's
// features are lost) the frame becomes the next reference, topped up with new corners.
// A frame whose tracking fails keeps the last tracked frame as reference (the next frame is tracked from it)
// and gets a constant-velocity pose; after max_bridged_frames such frames tracking restarts.
// Not thread-safe: one thread calls Track() with the frames in order.
class StereoOdometry {
 public:
  // Throws InvalidOption when `options` or `calibration` is invalid.
  StereoOdometry(const StereoOdometryOptions& options, const StereoCalibration& calibration);
  ~StereoOdometry();
  StereoOdometry(const StereoOdometry&) = delete;
  StereoOdometry& operator=(const StereoOdometry&) = delete;

  // The pose of the first frame (default identity); only before the first Track().
  void SetFirstPose(const Pose3d& world_from_cam);

  // The pose of the frame (rectified CV_8UC1 or CV_8UC3 pair of the calibration's size) taken at
  // `timestamp_s`. Throws std::invalid_argument when the images do not fit the calibration.
  OdometryResult Track(const cv::Mat& left, const cv::Mat& right, double timestamp_s);

  int frames_tracked() const { return frames_tracked_; }
  int frames_bridged() const { return frames_bridged_; }
  int restarts() const { return restarts_; }

 private:
  struct State;
  StereoOdometryOptions options_;
  StereoCalibration calibration_;
  std::unique_ptr<State> state_;
  int frames_tracked_ = 0;
  int frames_bridged_ = 0;
  int restarts_ = 0;
};

}  // namespace semap
