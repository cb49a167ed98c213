// The drive: lane-following along the streets of the grid city, with circular arcs at the turns.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

// One piece of the planar path: a straight line (curvature 0) or a circular arc, parametrised by arc length.
struct PathPiece {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  double start_heading_rad = 0.0;  // counter-clockwise from the scene x axis
  double length_m = 0.0;
  double curvature_per_m = 0.0;  // > 0 turns left

  Eigen::Vector2d PositionAt(double s_m) const;
  double HeadingAt(double s_m) const { return start_heading_rad + curvature_per_m * s_m; }
};

// Poses of the IMU in the scene frame (z up, road at z = 0) at each frame. Immutable after Generate();
// thread-safe to read.
class Trajectory {
 public:
  // Deterministic in options (seed, speed, turns, frame count, city layout).
  static Trajectory Generate(const SynthOptions& options, double imu_height_m);

  int num_frames() const { return static_cast<int>(scene_from_imu_.size()); }
  const Pose3d& scene_from_imu(int frame) const { return scene_from_imu_.at(frame); }
  double timestamp_s(int frame) const { return frame / frame_rate_hz_; }
  // Turns actually driven (can be fewer than asked on a short drive).
  int num_turns() const { return num_turns_; }
  double length_m() const { return length_m_; }
  const std::vector<PathPiece>& pieces() const { return pieces_; }
  // Points along the path every `step_m` (for laying out the scene around it).
  std::vector<Eigen::Vector2d> Sample(double step_m) const;

 private:
  std::vector<Pose3d> scene_from_imu_;
  std::vector<PathPiece> pieces_;
  double frame_rate_hz_ = 10.0;
  double length_m_ = 0.0;
  int num_turns_ = 0;
};

}  // namespace semap::sim
