// Robust Gauss-Newton refinement of the motion between two stereo frames from their matched features (not
// API). Every residual is in pixels of one of the four images, so that one threshold fits them all.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "engine/core/calibration.h"

namespace semap::odometry_internal {

// A feature seen in both frames: left (u, v) and right u in the reference frame, left (u, v) in the current
// one and, when has_current_right, its right u there.
struct StereoMatch {
  Eigen::Vector2d ref_left_px;
  double ref_right_u_px = 0.0;
  Eigen::Vector2d cur_left_px;
  double cur_right_u_px = 0.0;
  bool has_current_right = false;
};

struct RefinerOptions {
  int iterations = 8;                // Gauss-Newton steps per round
  int rounds = 3;                    // rounds of (steps, then inliers re-chosen from all matches)
  double huber_px = 1.0;             // Huber kernel width of each residual, px
  double inlier_threshold_px = 1.5;  // largest residual of an inlier, px
  double min_disparity_px = 1.0;     // a side below this disparity is not triangulated
  // Added to every measured disparity before triangulation: true = measured + offset at the pixel's row (a
  // stereo rig whose rectification is off by a fraction of a pixel).
  DisparityOffset disparity_offset;
  // Also estimate the offset from how the depths of the two frames agree with the motion, starting from
  // disparity_offset: 0 = no, 1 = its constant (a seventh unknown), 2 = its constant and per-row term.
  int estimate_offset_terms = 0;
};

struct RefinedMotion {
  Pose3d cur_from_ref = Pose3d::Identity();
  std::vector<bool> inliers;  // per match
  int num_inliers = 0;
  double rms_px = 0.0;               // of the inliers' residuals
  DisparityOffset disparity_offset;  // the offset used (estimated when asked)
  // When estimated: the information on the estimated terms (constant, per row) with the pose marginalised,
  // in 1/px² (unestimated terms: 0); and the constant's standard deviation (infinite when the motion cannot
  // tell it), px.
  Eigen::Matrix2d offset_information = Eigen::Matrix2d::Zero();
  double disparity_offset_sigma_px = 0.0;
};

// Refines `cur_from_ref` (the P3P estimate) by minimising, over the matches, the reprojection of the
// reference frame's triangulated features into the current left and right images and of the current ones
// into the reference images (both directions, so that the depth noise of either frame averages out).
// `start_inliers` (per match) are used in the first round; later rounds re-choose them by the threshold.
RefinedMotion RefineStereoMotion(const StereoCalibration& calibration,
                                 const std::vector<StereoMatch>& matches, const Pose3d& cur_from_ref,
                                 const std::vector<bool>& start_inliers, const RefinerOptions& options);

}  // namespace semap::odometry_internal
