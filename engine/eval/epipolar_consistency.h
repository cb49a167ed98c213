// Do a sequence's poses agree with its images? An odometry-free check of a pose reference: image points
// tracked from frame a to frame b must lie on the epipolar lines that the poses' relative motion b_from_a
// draws. The Sampson distance (the first-order distance of a match to the epipolar geometry, in px) of every
// track, under the poses as given and under the poses of a camera frame rotated by a fixed R (an extrinsic
// calibration between the pose source and the camera off by R), tells how far the poses are from what the
// images show, with no stereo, no depth and no estimator in between.
#pragma once

#include <vector>

#include "engine/core/calibration.h"

namespace semap {

// One window of tracks: pixels in frame a and the same scene points in frame b, and the poses' relative
// motion (camera b from camera a).
struct TrackWindow {
  std::vector<Eigen::Vector2d> a_px;
  std::vector<Eigen::Vector2d> b_px;  // same size as a_px
  Pose3d b_from_a = Pose3d::Identity();
};

// The Sampson distance (px) of the match (a_px, b_px) under the motion (R, t) = b_from_a of a pinhole camera
// with these intrinsics (fx, fy, cx, cy): |x_bᵀ F x_a| / sqrt((F x_a)₁² + (F x_a)₂² + (Fᵀ x_b)₁² + (Fᵀ
// x_b)₂²), F = K⁻ᵀ [t]ₓ R K⁻¹. 0 for a motion without translation (no epipolar geometry).
double SampsonDistancePx(const StereoCalibration& intrinsics, const Pose3d& b_from_a,
                         const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px);

struct EpipolarAgreement {
  double mean_px = 0.0;    // of the distances, each capped at the cap (a mistrack or a moving object counts
                           // as the cap, not as its own size)
  double median_px = 0.0;  // of the distances
  int tracks = 0;
};

// Every track of every window under the windows' motions seen from a camera frame rotated by
// `truth_from_image` (R: a direction d in the images' camera frame is R·d in the poses' camera frame, so a
// window's motion becomes Rᵀ·(b_from_a)·R). Identity = the poses as given.
EpipolarAgreement EpipolarAgreementOf(const std::vector<TrackWindow>& windows,
                                      const StereoCalibration& intrinsics,
                                      const Eigen::Matrix3d& truth_from_image, double cap_px);

// The fixed rotation R that minimises EpipolarAgreementOf(...).mean_px, by coordinate descent on its rotation
// vector (steps from start_step_deg down to min_step_deg), from the identity.
struct EpipolarRotationFit {
  Eigen::Matrix3d truth_from_image = Eigen::Matrix3d::Identity();
  Eigen::Vector3d angles_deg = Eigen::Vector3d::Zero();  // R's rotation vector, degrees (about x, y, z)
  EpipolarAgreement agreement;                           // with R
};
EpipolarRotationFit FitEpipolarRotation(const std::vector<TrackWindow>& windows,
                                        const StereoCalibration& intrinsics, double cap_px,
                                        double start_step_deg = 0.4, double min_step_deg = 0.005);

}  // namespace semap
