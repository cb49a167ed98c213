// Accuracy of an estimated camera trajectory against the true one (e.g. visual odometry against KITTI's
// poses): the KITTI odometry metric, the relative pose error over a fixed number of frames and the absolute
// trajectory error after alignment. Both trajectories are world_from_cam poses of the same frames, in order.
#pragma once

#include <vector>

#include "engine/core/calibration.h"

namespace semap {

// Mean drift over segments: translation error as a percentage of the segment's length and rotation error in
// degrees per metre of it.
struct SegmentDrift {
  double length_m = 0.0;  // the segment length (KITTI metric), or the mean segment length (relative error)
  int segments = 0;       // how many segments were averaged (0: the drive is too short)
  double translation_percent = 0.0;
  double rotation_deg_per_m = 0.0;
};

struct KittiOdometryOptions {
  std::vector<double> lengths_m = {100, 200, 300, 400, 500, 600, 700, 800};  // KITTI devkit
  int step_frames = 10;  // a segment starts every step_frames frames (KITTI devkit)
};

struct KittiOdometryError {
  std::vector<SegmentDrift> per_length;  // one per length that has segments
  SegmentDrift overall;                  // over every segment of every length (the leaderboard's figure)
};

// The KITTI odometry benchmark's metric (devkit evaluate_odometry): segments of each length, starting every
// step_frames frames, each error the pose of the segment end relative to its start against the truth.
KittiOdometryError KittiOdometryMetric(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                       const KittiOdometryOptions& options = {});

// Relative pose error over every window of `delta_frames` frames (segments start at every frame); a window in
// which the truth moves less than min_length_m is left out of the per-metre figures (standing still).
struct RelativePoseError {
  SegmentDrift drift;               // mean % and deg/m over the windows
  double translation_rmse_m = 0.0;  // RMS of the windows' translation errors
  double rotation_rmse_deg = 0.0;
  int windows = 0;
};
RelativePoseError RelativeError(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                int delta_frames, double min_length_m = 0.5);

// A diagnostic, not a score (it is fitted on the truth): the fixed rotation R of the camera frame that best
// turns the estimate's motions into the truth's, as if the truth's poses were of a camera frame rotated by R
// from the estimate's (an extrinsic calibration between the pose source and the camera off by R, or a camera
// model that sees the motion in a rotated frame). R maps each window's estimated translation direction and
// rotation vector onto the truth's (windows of `delta_frames`; Kabsch/Wahba in closed form), with a weak pull
// towards the identity so that a straight drive, which cannot tell a roll about its direction, gets none.
// `relative` is the relative pose error with R taken out: truth_i · R against the estimate. A drift that one
// fixed R explains is a frame disagreement, not an error that accumulates along the drive.
struct FrameRotationFit {
  Eigen::Matrix3d truth_cam_from_estimate_cam = Eigen::Matrix3d::Identity();  // R
  // R as a rotation vector, degrees (about the camera's x, y, z).
  Eigen::Vector3d angles_deg = Eigen::Vector3d::Zero();
  RelativePoseError relative;  // with R taken out
};
FrameRotationFit FitFrameRotation(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate,
                                  int delta_frames, double min_length_m = 0.5);

// Absolute trajectory error: camera positions after the rigid (rotation + translation, no scale) alignment
// of the estimate onto the truth that minimises it (Umeyama / Horn), and the end-point error without any
// alignment but the common first pose.
struct AbsoluteTrajectoryError {
  double rmse_m = 0.0;
  double mean_m = 0.0;
  double max_m = 0.0;
  double end_point_m = 0.0;        // last position, both trajectories put at the same first pose
  double end_point_percent = 0.0;  // of the true path length
  double end_rotation_deg = 0.0;   // last orientation, same
  double path_length_m = 0.0;      // of the truth
};
AbsoluteTrajectoryError AbsoluteError(const std::vector<Pose3d>& truth, const std::vector<Pose3d>& estimate);

}  // namespace semap
