// `semap synth` run as a user would: a tiny sequence, and bad arguments.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

using test::CliRun;
using test::RunSemap;

namespace fs = std::filesystem;

// Small images keep the test fast; --set reaches the synth config section.
const std::string kSmall =
    " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160"
    " --set synth.cy_px=48 --set synth.lidar_azimuth_steps=256";

TEST(SemapSynth, WritesAKittiRawSequence) {
  const fs::path out = test::TempDir() / "out";
  const CliRun r = RunSemap("synth --preset vegetated --frames 3 --seed 4 --speed-mps 5 --turns 0 --out " +
                            out.string() + kSmall);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("wrote 3 frames")) << r.output;
  EXPECT_TRUE(r.Has("class composition")) << r.output;
  const fs::path drive = out / "2026_01_01" / "2026_01_01_drive_0001_sync";
  for (const char* f : {"image_02/data/0000000002.png", "image_03/data/0000000002.png",
                        "velodyne_points/data/0000000002.bin", "oxts/data/0000000002.txt",
                        "semantic/data/0000000002.png", "depth/data/0000000002.png", "scene_mesh.ply"}) {
    EXPECT_TRUE(fs::exists(drive / f)) << f;
  }
  EXPECT_TRUE(fs::exists(out / "2026_01_01" / "calib_cam_to_cam.txt"));
  const std::string text = test::ReadFile(out / "2026_01_01" / "calib_cam_to_cam.txt");
  EXPECT_NE(text.find("S_rect_02: 3.200000000000e+02 9.600000000000e+01"), std::string::npos) << text;
}

TEST(SemapSynth, WritesAMultiViewSetInTheStrechaLayout) {
  const fs::path dir = test::TempDir(), out = dir / "set", bad = dir / "bad";
  const CliRun r = RunSemap("synth --layout strecha --frames 2 --seed 4 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("wrote 2 views")) << r.output;
  for (const char* f :
       {"images/0000.png", "images/0001.png", "images/K.txt", "gt_dense_cameras/0001.png.camera",
        "labels/0001.png", "depth/0001.png", "scene_mesh.ply"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  EXPECT_FALSE(fs::exists(out / "images/0002.png"));
  const std::string camera = test::ReadFile(out / "gt_dense_cameras/0000.png.camera");
  EXPECT_NE(camera.find("\n0 0 0\n"), std::string::npos) << camera;
  EXPECT_NE(camera.find("\n768 512\n"), std::string::npos) << camera;
  // The street's options do not apply to it.
  const CliRun refused = RunSemap("synth --layout strecha --preset urban --out " + bad.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_TRUE(refused.Has("--preset")) << refused.output;
  EXPECT_EQ(RunSemap("synth --layout colmap --out " + bad.string()).exit_code, 2);
  EXPECT_FALSE(fs::exists(bad));
}

TEST(SemapSynth, BadArgumentsAreUsageErrors) {
  const fs::path out = test::TempDir() / "bad";
  EXPECT_EQ(RunSemap("synth --preset suburban --frames 2 --out " + out.string()).exit_code, 2);
  EXPECT_EQ(RunSemap("synth --frames 2").exit_code, 2);  // --out is required
  const CliRun r = RunSemap("synth --frames 2 --set synth.block_pitch_m=10 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.Has("block_pitch_m")) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(SemapSynth, UnwritableOutputIsAFailure) {
  const fs::path file = test::TempDir() / "a_file";
  std::ofstream(file) << "x";
  const CliRun r = RunSemap("synth --frames 1 --out " + (file / "sub").string() + kSmall);
  EXPECT_EQ(r.exit_code, 1) << r.output;
}

}  // namespace
}  // namespace semap::tools
