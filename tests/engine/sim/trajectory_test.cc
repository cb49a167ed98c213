#include "engine/sim/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/check.h"

namespace semap::sim {
namespace {

SynthOptions Drive(int frames, int turns, double speed) {
  SynthOptions o;
  o.num_frames = frames;
  o.num_turns = turns;
  o.speed_mps = speed;
  o.seed = 4;
  return o;
}

TEST(Trajectory, ConstantSpeedAndHeightAndRequestedTurns) {
  const SynthOptions o = Drive(400, 2, 8.0);
  const Trajectory t = Trajectory::Generate(o, 0.93);
  ASSERT_EQ(t.num_frames(), 400);
  EXPECT_EQ(t.num_turns(), 2);
  const double step = o.speed_mps / o.frame_rate_hz;
  double yaw_change = 0.0;
  for (int i = 1; i < t.num_frames(); ++i) {
    const Pose3d& a = t.scene_from_imu(i - 1);
    const Pose3d& b = t.scene_from_imu(i);
    // Chord of an arc of length `step` is at most this much shorter than the arc.
    const double dist = (b.translation() - a.translation()).head<2>().norm();
    EXPECT_LE(dist, step + 1e-9);
    EXPECT_GE(dist, step * (1.0 - step * step / (24.0 * o.turn_radius_m * o.turn_radius_m)) - 1e-9);
    EXPECT_NEAR(b.translation().z(), 0.93, 1e-12);
    const Eigen::Vector3d fa = a.linear().col(0), fb = b.linear().col(0);
    yaw_change += std::atan2(fa.x() * fb.y() - fa.y() * fb.x(), fa.head<2>().dot(fb.head<2>()));
  }
  // Two 90-degree turns: the total heading change is 0 or +-180 degrees.
  const double turns = std::abs(yaw_change) / (M_PI / 2);
  EXPECT_TRUE(std::abs(turns) < 0.05 || std::abs(turns - 2.0) < 0.05) << yaw_change;
  EXPECT_NEAR(t.timestamp_s(10), 1.0, 1e-12);
  EXPECT_GE(t.length_m(), step * 399);
}

TEST(Trajectory, StaysInItsLaneOnTheGrid) {
  const SynthOptions o = Drive(600, 3, 10.0);
  const Trajectory t = Trajectory::Generate(o, 0.93);
  for (int i = 0; i < t.num_frames(); ++i) {
    const Eigen::Vector2d p = t.scene_from_imu(i).translation().head<2>();
    // Distance to the nearest street centre line (x or y a multiple of the pitch) stays on the carriageway.
    const double dx = std::abs(p.x() - o.block_pitch_m * std::round(p.x() / o.block_pitch_m));
    const double dy = std::abs(p.y() - o.block_pitch_m * std::round(p.y() / o.block_pitch_m));
    EXPECT_LT(std::min(dx, dy), 0.5 * o.road_width_m - 1.0) << "frame " << i;
  }
}

TEST(Trajectory, ShortDriveHasFewerTurnsAndIsDeterministic) {
  const Trajectory a = Trajectory::Generate(Drive(20, 5, 8.0), 0.93);
  EXPECT_EQ(a.num_turns(), 0);
  const Trajectory b = Trajectory::Generate(Drive(20, 5, 8.0), 0.93);
  for (int i = 0; i < a.num_frames(); ++i)
    EXPECT_TRUE(a.scene_from_imu(i).isApprox(b.scene_from_imu(i), 0.0));
  const Trajectory still = Trajectory::Generate(Drive(5, 0, 0.0), 0.93);
  EXPECT_TRUE(still.scene_from_imu(0).translation().isApprox(still.scene_from_imu(4).translation()));
}

TEST(SynthOptions, CheckRejectsBadValues) {
  SynthOptions o;
  EXPECT_NO_THROW(o.Check());
  o.num_frames = 0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = SynthOptions{};
  o.block_pitch_m = 20.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = SynthOptions{};
  o.lidar_range_noise_m = -1.0;
  EXPECT_THROW(o.Check(), InvalidOption);
}

}  // namespace
}  // namespace semap::sim
