// `semap info` run as a user would: on a tiny raw sequence written by the test, and on bad paths.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

using test::CliRun;
using test::RunSemap;

TEST(SemapInfo, TinyRawSequence) {
  const auto t = test::WriteTinyRaw(test::TempDir() / "raw");
  const CliRun r = RunSemap("info " + t.date.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("layout       kitti_raw")) << r.output;
  EXPECT_TRUE(r.Has("frames       4 (ids 0..3")) << r.output;
  EXPECT_TRUE(r.Has("image size   32 x 16 px, colour")) << r.output;
  EXPECT_TRUE(r.Has("fx 100.0000  fy 101.0000  cx 15.5000  cy 7.5000 px, baseline 0.540000 m")) << r.output;
  EXPECT_TRUE(r.Has("poses        yes")) << r.output;
  EXPECT_TRUE(r.Has("velodyne     yes")) << r.output;
  EXPECT_TRUE(r.Has("labels       yes")) << r.output;
  // Labels: bottom half road, top half building, one of 32 columns car.
  EXPECT_TRUE(r.Has("over 4 of 4 label images (scheme cityscapes)")) << r.output;
  EXPECT_TRUE(r.Has("ground         48.4 %")) << r.output;
  EXPECT_TRUE(r.Has("wall           48.4 %")) << r.output;
  EXPECT_TRUE(r.Has("car             3.1 %")) << r.output;
}

TEST(SemapInfo, BadInputGivesMessageAndExitCode) {
  const auto dir = test::TempDir();
  CliRun r = RunSemap("info " + (dir / "missing").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has((dir / "missing").string() + ": dataset folder not found")) << r.output;
  const auto t = test::WriteTinyRaw(dir / "raw");
  r = RunSemap("info " + t.root.string() + " --set input.max_frames=-1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.Has("input.max_frames")) << r.output;
  test::WriteTextFile(t.date / "calib_cam_to_cam.txt", "P_rect_02: 1 2 3\n");
  r = RunSemap("info " + t.root.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has("calib_cam_to_cam.txt: key 'P_rect_02' has 3 values, expected 12")) << r.output;
  r = RunSemap("info");
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace semap::tools
