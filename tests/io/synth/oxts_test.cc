#include "io/synth/oxts.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/sim/internal/random.h"
#include "engine/sim/synthetic_sequence.h"
#include "io/synth/kitti_raw_writer.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

// The packet as a reader gets it back from an OXTS file written by the generator's writer.
OxtsPacket ThroughFile(const OxtsPacket& p) {
  const auto path = test::ProcessTempRoot() / "oxts_roundtrip.txt";
  WriteOxtsFile(path, p);
  return ReadOxtsFile(path);
}

// The KITTI devkit's convertOxtsToPose.m, written out independently of the code under test.
Pose3d DevkitPose(const OxtsPacket& p, double scale) {
  const double er = 6378137.0;
  const double tx = scale * p.lon_deg * M_PI * er / 180.0;
  const double ty = scale * er * std::log(std::tan((90.0 + p.lat_deg) * M_PI / 360.0));
  const double rx = p.roll_rad, ry = p.pitch_rad, rz = p.yaw_rad;
  Eigen::Matrix3d Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, std::cos(rx), -std::sin(rx), 0, std::sin(rx), std::cos(rx);
  Ry << std::cos(ry), 0, std::sin(ry), 0, 1, 0, -std::sin(ry), 0, std::cos(ry);
  Rz << std::cos(rz), -std::sin(rz), 0, std::sin(rz), std::cos(rz), 0, 0, 0, 1;
  Pose3d pose = Pose3d::Identity();
  pose.linear() = Rz * Ry * Rx;
  pose.translation() = Eigen::Vector3d(tx, ty, p.alt_m);
  return pose;
}

TEST(Oxts, InverseMatchesTheDevkitForwardConversion) {
  sim::sim_internal::Rng rng(3);
  const double scale = std::cos(49.0 * M_PI / 180.0);
  for (int k = 0; k < 200; ++k) {
    Pose3d pose = Pose3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(rng.Uniform(-M_PI, M_PI), Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(rng.Uniform(-0.3, 0.3), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(rng.Uniform(-0.3, 0.3), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() =
        Eigen::Vector3d(rng.Uniform(5.9e5, 6.3e5), rng.Uniform(4.1e6, 4.2e6), rng.Uniform(50, 500));
    const OxtsPacket p = ThroughFile(OxtsFromMercatorPose(pose, scale));
    const Pose3d back = DevkitPose(p, scale);
    EXPECT_LT((back.translation() - pose.translation()).norm(), 1e-6);
    EXPECT_LT((back.linear() - pose.linear()).norm(), 1e-12);
    OxtsPacket first;
    first.lat_deg = 49.0;
    EXPECT_TRUE(OxtsPoseConverter(first).MercatorPose(p).isApprox(back, 1e-14));
  }
}

// The whole chain as a KITTI reader does it: OXTS text -> devkit poses (scale of the first frame) ->
// normalised by the first pose -> IMU trajectory; and the camera through cam2_from_imu.
TEST(Oxts, SequencePacketsRecoverTheTrajectorySubMillimetre) {
  sim::SynthOptions o;
  o.num_frames = 300;
  o.num_turns = 1;
  o.speed_mps = 9.0;
  o.seed = 5;
  const sim::SyntheticSequence seq(o);
  ASSERT_EQ(seq.trajectory().num_turns(), 1);
  const auto packets = SynthOxtsPackets(seq);
  ASSERT_EQ(static_cast<int>(packets.size()), seq.num_frames());
  std::vector<OxtsPacket> parsed;
  for (const auto& p : packets) parsed.push_back(ThroughFile(p));
  EXPECT_EQ(parsed[0].lat_deg, o.origin_latitude_deg);
  EXPECT_EQ(parsed[0].lon_deg, o.origin_longitude_deg);
  const double scale = std::cos(parsed[0].lat_deg * M_PI / 180.0);
  const Pose3d pose0_inv = DevkitPose(parsed[0], scale).inverse();
  const Pose3d cam2_from_imu = seq.rig().cam2_from_imu();
  double worst_m = 0.0, worst_rot = 0.0;
  for (int i = 0; i < seq.num_frames(); ++i) {
    const Pose3d world_from_imu = pose0_inv * DevkitPose(parsed[i], scale);
    const Pose3d truth = seq.world_from_scene() * seq.scene_from_imu(i);
    worst_m = std::max(worst_m, (world_from_imu.translation() - truth.translation()).norm());
    worst_rot = std::max(worst_rot, (world_from_imu.linear() - truth.linear()).norm());
    const Pose3d world_from_cam2 = world_from_imu * cam2_from_imu.inverse();
    EXPECT_LT((world_from_cam2.translation() - seq.world_from_cam2(i).translation()).norm(), 1e-3);
  }
  EXPECT_LT(worst_m, 1e-3);
  EXPECT_LT(worst_rot, 1e-9);
  RecordProperty("worst_position_error_m", std::to_string(worst_m));
  // The drive covers a real distance (the test is not trivially satisfied).
  EXPECT_GT((seq.world_from_cam2(seq.num_frames() - 1).translation()).norm(), 100.0);
}

}  // namespace
}  // namespace semap::io
