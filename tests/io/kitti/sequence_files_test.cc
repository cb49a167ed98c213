#include "io/kitti/sequence_files.h"

#include <gtest/gtest.h>

#include <functional>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

std::string WhatOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const FileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(KittiTimestamps, SecondsSinceFirstLine) {
  const fs::path path = test::TempDir() / "timestamps.txt";
  test::WriteTextFile(path,
                      "2011-09-26 13:02:25.964389445\n2011-09-26 13:02:26.068074971\n"
                      "2011-09-26 23:59:59.500000000\n2011-09-27 00:00:00.250000000\n\n");
  const auto t = ReadKittiTimestamps(path);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0], 0.0);
  EXPECT_NEAR(t[1], 0.103685526, 1e-6);
  EXPECT_NEAR(t[2], 10 * 3600 + 57 * 60 + 33.535610555, 1e-6);
  EXPECT_NEAR(t[3] - t[2], 0.75, 1e-6);  // across midnight
}

TEST(KittiTimestamps, MalformedLine) {
  const fs::path path = test::TempDir() / "timestamps.txt";
  test::WriteTextFile(path, "2011-09-26 13:02:25.964389445\n2011-09-26 13:02\n");
  EXPECT_NE(WhatOf([&] { ReadKittiTimestamps(path); }).find(path.string() + ": line 2: '2011-09-26 13:02'"),
            std::string::npos);
  test::WriteTextFile(path, "2011-02-30 13:02:25.9\n");
  EXPECT_NE(WhatOf([&] { ReadKittiTimestamps(path); }).find("line 1"), std::string::npos);
}

TEST(KittiOdometryTimes, SecondsSinceFirstLine) {
  const fs::path path = test::TempDir() / "times.txt";
  test::WriteTextFile(path, "1.000000e-01\n2.036e-01\n3.1e-01\n");
  const auto t = ReadOdometryTimes(path);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t[1], 2.036e-01 - 1.0e-01);
  test::WriteTextFile(path, "0.1\nabc\n");
  EXPECT_NE(WhatOf([&] { ReadOdometryTimes(path); }).find("line 2: 'abc' is not a time in seconds"),
            std::string::npos);
}

TEST(KittiOdometryPoses, ReadsRowMajorAndChecksLength) {
  const fs::path path = test::TempDir() / "03.txt";
  test::WriteTextFile(path,
                      "1 0 0 0 0 1 0 0 0 0 1 0\n"
                      "0 -1 0 1.5 1 0 0 -2 0 0 1 3.25\n");
  const auto poses = ReadOdometryPoses(path, 2);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_TRUE(poses[0].isApprox(Pose3d::Identity()));
  EXPECT_EQ(poses[1].translation(), Eigen::Vector3d(1.5, -2, 3.25));
  EXPECT_EQ(poses[1].linear()(0, 1), -1.0);
  EXPECT_EQ(poses[1].linear()(1, 0), 1.0);
  EXPECT_EQ(ReadOdometryPoses(path, 1).size(), 1u);
  EXPECT_EQ(WhatOf([&] { ReadOdometryPoses(path, 5); }),
            path.string() + ": has 2 poses but 5 frames need one each");
  test::WriteTextFile(path, "1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_NE(WhatOf([&] { ReadOdometryPoses(path, 1); }).find("line 1 is not 12 finite numbers"),
            std::string::npos);
  test::WriteTextFile(path, "1 0 0 0 0 1 0 0 0 0 1 nan\n");
  EXPECT_NE(WhatOf([&] { ReadOdometryPoses(path, 1); }).find("line 1 is not 12 finite numbers"),
            std::string::npos);
  EXPECT_NE(
      WhatOf([&] { ReadOdometryPoses(path.parent_path() / "none.txt", 1); }).find("poses file not found"),
      std::string::npos);
}

}  // namespace
}  // namespace semap::io
