#include "engine/sim/trajectory.h"

#include <algorithm>
#include <cmath>

#include "engine/core/check.h"
#include "engine/sim/internal/random.h"

namespace semap::sim {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
// Wavelengths of the body roll and pitch oscillation along the path.
constexpr double kRollWavelengthM = 23.0;
constexpr double kPitchWavelengthM = 37.0;
// Where the drive starts along its first street, as a fraction of the block pitch past an intersection.
constexpr double kStartFraction = 0.35;

Eigen::Vector2d Dir(double heading) { return {std::cos(heading), std::sin(heading)}; }

}  // namespace

Eigen::Vector2d PathPiece::PositionAt(double s) const {
  if (curvature_per_m == 0.0) return start + s * Dir(start_heading_rad);
  const double k = curvature_per_m;
  const double h0 = start_heading_rad, h1 = start_heading_rad + k * s;
  return start + Eigen::Vector2d(std::sin(h1) - std::sin(h0), std::cos(h0) - std::cos(h1)) / k;
}

Trajectory Trajectory::Generate(const SynthOptions& o, double imu_height_m) {
  o.Check();
  sim_internal::Rng rng(sim_internal::HashCombine(o.seed, 0x7472616aULL));
  const double step_m = o.speed_mps / o.frame_rate_hz;
  const double needed_m = step_m * (o.num_frames - 1) + 1e-9;
  const double pitch = o.block_pitch_m, off = o.lane_offset_m, r = o.turn_radius_m;

  // Intersections crossed by a straight drive of the needed length, and which of them get a turn.
  const double start_dist = kStartFraction * pitch;  // from the previous intersection
  const int crossings = static_cast<int>(std::floor((needed_m + start_dist) / pitch));
  // A turn needs the arc to fit before the end of the drive and leave a straight stretch after it.
  const int usable = std::max(0, crossings - 1);
  const int turns = std::min(o.num_turns, usable);
  std::vector<int> turn_at(crossings + 2, 0);  // 0 straight, +1 left, -1 right
  for (int k = 0; k < turns; ++k) {
    const int idx = static_cast<int>(std::lround((k + 1.0) * usable / (turns + 1.0)));
    turn_at[std::clamp(idx, 0, crossings)] = rng.Bernoulli(0.5) ? 1 : -1;
  }
  int turns_done = 0;

  Trajectory t;
  t.frame_rate_hz_ = o.frame_rate_hz;
  // The lane of the first street: centre line y = 0, heading +x, driving on the right (y = -off).
  Eigen::Vector2d pos(start_dist, -off);
  double heading = 0.0;
  Eigen::Vector2d next_cross(pitch, 0.0);  // the next intersection centre
  double total = 0.0;
  for (int c = 0; total < needed_m + pitch; ++c) {
    const int turn = c < static_cast<int>(turn_at.size()) ? turn_at[c] : 0;
    const Eigen::Vector2d d = Dir(heading);
    const double dist_to_cross = (next_cross - pos).dot(d);
    if (turn == 0) {
      // Straight through: a line to the intersection, the next one a block further.
      t.pieces_.push_back({pos, heading, dist_to_cross, 0.0});
      total += dist_to_cross;
      pos += dist_to_cross * d;
      next_cross += pitch * d;
      continue;
    }
    ++turns_done;
    // Left turn: the arc starts and ends (R - off) from the intersection; right turn: (R + off).
    const double pre = turn > 0 ? r - off : r + off;
    t.pieces_.push_back({pos, heading, dist_to_cross - pre, 0.0});
    total += dist_to_cross - pre;
    pos += (dist_to_cross - pre) * d;
    const PathPiece arc{pos, heading, kHalfPi * r, turn / r};
    t.pieces_.push_back(arc);
    total += arc.length_m;
    pos = arc.PositionAt(arc.length_m);
    heading = arc.HeadingAt(arc.length_m);
    const Eigen::Vector2d nd = Dir(std::round(heading / kHalfPi) * kHalfPi);
    heading = std::atan2(nd.y(), nd.x());
    next_cross = next_cross + pitch * nd;
  }
  t.num_turns_ = turns_done;
  for (const auto& p : t.pieces_) t.length_m_ += p.length_m;

  const double roll_phase = rng.Uniform(0.0, 2.0 * M_PI), pitch_phase = rng.Uniform(0.0, 2.0 * M_PI);
  t.scene_from_imu_.reserve(o.num_frames);
  size_t piece = 0;
  double piece_start = 0.0;
  for (int i = 0; i < o.num_frames; ++i) {
    const double s = step_m * i;
    while (piece + 1 < t.pieces_.size() && s > piece_start + t.pieces_[piece].length_m) {
      piece_start += t.pieces_[piece].length_m;
      ++piece;
    }
    const PathPiece& pp = t.pieces_[piece];
    const Eigen::Vector2d xy = pp.PositionAt(s - piece_start);
    const double yaw = pp.HeadingAt(s - piece_start);
    const double roll = o.body_wobble_rad * std::sin(2.0 * M_PI * s / kRollWavelengthM + roll_phase);
    const double pitch_rad = o.body_wobble_rad * std::sin(2.0 * M_PI * s / kPitchWavelengthM + pitch_phase);
    Pose3d pose = Pose3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(xy.x(), xy.y(), imu_height_m);
    t.scene_from_imu_.push_back(pose);
  }
  return t;
}

std::vector<Eigen::Vector2d> Trajectory::Sample(double step_m) const {
  SEMAP_ASSERT(step_m > 0.0);
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : pieces_) {
    const int n = std::max(1, static_cast<int>(std::ceil(p.length_m / step_m)));
    for (int k = 0; k <= n; ++k) out.push_back(p.PositionAt(p.length_m * k / n));
  }
  return out;
}

}  // namespace semap::sim
