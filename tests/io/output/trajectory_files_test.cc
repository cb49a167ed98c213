#include "io/output/trajectory_files.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>

#include "tests/common/test_data.h"

namespace semap::io {
namespace {

std::vector<Pose3d> Poses() {
  std::vector<Pose3d> out;
  for (int i = 0; i < 4; ++i) {
    Pose3d p = Pose3d::Identity();
    p.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(0.5 * i, -0.01 * i, 1.3 * i);
    out.push_back(p);
  }
  return out;
}

TEST(TrajectoryFiles, KittiPosesRoundTrip) {
  const auto path = test::TempDir() / "poses.txt";
  WriteKittiPoses(path, Poses());
  const std::vector<Pose3d> back = ReadKittiPoses(path);
  ASSERT_EQ(back.size(), 4u);
  for (size_t i = 0; i < back.size(); ++i) EXPECT_TRUE(back[i].isApprox(Poses()[i], 1e-8)) << i;
}

TEST(TrajectoryFiles, TumRoundTrip) {
  const auto path = test::TempDir() / "poses.tum";
  std::vector<StampedPose> poses;
  for (size_t i = 0; i < Poses().size(); ++i) poses.push_back({0.1 * static_cast<double>(i), Poses()[i]});
  WriteTumTrajectory(path, poses);
  const std::vector<StampedPose> back = ReadTumTrajectory(path);
  ASSERT_EQ(back.size(), 4u);
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_NEAR(back[i].timestamp_s, 0.1 * static_cast<double>(i), 1e-6);
    EXPECT_TRUE(back[i].world_from_cam.isApprox(Poses()[i], 1e-7)) << i;
  }
}

TEST(TrajectoryFiles, MalformedLinesAreNamed) {
  const auto dir = test::TempDir();
  std::ofstream(dir / "bad.tum") << "# header\n0 1 2 3 0 0 0 1\n0.1 1 2 3 0 0 0\n";
  try {
    ReadTumTrajectory(dir / "bad.tum");
    FAIL() << "a line of 7 numbers was accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "scaled.tum") << "0 1 2 3 0 0 0 2\n";
  EXPECT_THROW(ReadTumTrajectory(dir / "scaled.tum"), FileError);
  std::ofstream(dir / "bad.txt") << "1 0 0 0 0 1 0 0 0 0 1\n";
  EXPECT_THROW(ReadKittiPoses(dir / "bad.txt"), FileError);
  EXPECT_THROW(ReadKittiPoses(dir / "missing.txt"), FileError);
}

}  // namespace
}  // namespace semap::io
