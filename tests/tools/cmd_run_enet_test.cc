// `semap run` with ENet labels on keyframes (semantics.enet_every_frames), end to end on a small
// generated sequence: the segment thread is reported, and the result depends on the configuration only, not
// on the threads' timing (the same mesh, byte for byte, from a run with 1 depth worker and one with 3).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

constexpr const char* kModel = "models/enet-cityscapes/enet-model.net";

class RunEnet : public ::testing::Test {
 protected:
  static fs::path Sequence() { return test::ProcessTempRoot() / "RunEnet_sequence"; }

  static void SetUpTestSuite() {
    fs::remove_all(Sequence());
    const CliRun r =
        test::RunSemap("synth --preset urban --frames 7 --seed 95 --out " + Sequence().string() +
                       " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160"
                       " --set synth.cy_px=48 --set synth.lidar_azimuth_steps=256");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }

  // `semap run` with ENet on keyframes every `every` frames into `out`; returns `out`.
  static fs::path RunWithEnet(const fs::path& out, int every, int depth_workers) {
    const CliRun r =
        test::RunSemap("run " + Sequence().string() + " --out " + out.string() + " --progress-interval 100" +
                       " --set semantics.source=enet --set semantics.enet_model_path=" +
                       (test::SharedDir() / kModel).string() +
                       " --set semantics.enet_input_width_px=512 --set semantics.enet_input_height_px=256" +
                       " --set semantics.enet_every_frames=" + std::to_string(every) +
                       " --set pipeline.depth_workers=" + std::to_string(depth_workers) +
                       " --set depth.max_points_per_frame=1500");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
  }

  static nlohmann::json Summary(const fs::path& out) {
    std::ifstream in(out / "summary.json");
    return nlohmann::json::parse(in);
  }
};

TEST_F(RunEnet, KeyframesAreSegmentedOnTheirOwnThreadAndReported) {
  SEMAP_REQUIRE_SHARED(kModel);
  const fs::path out = RunWithEnet(test::TempDir() / "every3", 3, 2);
  const nlohmann::json s = Summary(out);
  EXPECT_EQ(s["frames_processed"], 7);
  EXPECT_EQ(s["frames_failed"], 0);
  ASSERT_TRUE(s["stages"].contains("segment")) << s.dump();
  ASSERT_TRUE(s["stages"].contains("depth.label_wait")) << s.dump();
  EXPECT_GT(s["stages"]["segment"]["mean_ms"].get<double>(), 0.0);
  // frames.csv has the segment column.
  std::ifstream csv(out / "frames.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("segment_ms"), std::string::npos) << header;
}

TEST_F(RunEnet, TheMeshDependsOnTheConfigurationNotOnTiming) {
  SEMAP_REQUIRE_SHARED(kModel);
  const fs::path dir = test::TempDir();
  const std::string one = test::ReadTextFile(RunWithEnet(dir / "one_worker", 3, 1) / "mesh.ply");
  const std::string three = test::ReadTextFile(RunWithEnet(dir / "three_workers", 3, 3) / "mesh.ply");
  ASSERT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == three) << "ENet every 3 frames: the mesh differs between 1 and 3 depth workers";
}

}  // namespace
}  // namespace semap::tools
