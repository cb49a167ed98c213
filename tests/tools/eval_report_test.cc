// `semap run --eval` and `semap eval --json` (tools/eval_report): per-frame accuracy files a user can plot.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

TEST(SemapRunEval, WritesPerFrameAccuracyThatAgreesWithSemapEval) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "run";
  const CliRun run = RunSemap("run " + seq.string() + " --method PS --eval --progress-interval 100 --out " +
                              out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(run.Has("vs Velodyne")) << run.output;
  std::ifstream csv(out / "eval_frames.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("frame_id,lidar_rmse_m", 0), 0u) << line;
  int frames = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::stoi(line.substr(0, line.find(','))), frames) << line;
    const double rmse = std::stod(line.substr(line.find(',') + 1));
    EXPECT_GT(rmse, 0.0);
    ++frames;
  }
  EXPECT_EQ(frames, 3);

  // The same mesh read back by `semap eval` gives the same totals, up to mesh.ply's float32 coordinates (a
  // vertex moved by 1e-6 m flips a few pixels at silhouettes, and their errors are metres).
  const fs::path json = out / "again.json";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + (out / "mesh.ply").string() + " --json " +
                               json.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  const auto a = nlohmann::json::parse(std::ifstream(out / "eval.json"));
  const auto b = nlohmann::json::parse(std::ifstream(json));
  const double rmse_a = a["lidar"]["rmse_m"].get<double>(), rmse_b = b["lidar"]["rmse_m"].get<double>();
  EXPECT_NEAR(rmse_a, rmse_b, 0.01 * rmse_a);
  const double pixels_a = a["lidar"]["compared_pixels"].get<double>();
  EXPECT_NEAR(pixels_a, b["lidar"]["compared_pixels"].get<double>(), 0.005 * pixels_a);
  ASSERT_EQ(b["per_frame"].size(), 3u);
  EXPECT_TRUE(b["per_frame"][2].contains("exact_depth"));
}

TEST(SemapEval, TheExactSceneMeshIsAccurateAndComplete) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path json = test::TempDir() / "scene.json";
  const fs::path scene = seq / "2026_01_01" / "2026_01_01_drive_0001_sync" / "scene_mesh.ply";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + scene.string() + " --json " + json.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(eval.Has("vs scene mesh accuracy 100.0 %")) << eval.output;
  const auto j = nlohmann::json::parse(std::ifstream(json));
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["accuracy"].get<double>(), 1.0);
  // Truth samples come from the 16-bit millimetre depth PNGs: within a millimetre of the true surface.
  EXPECT_GT(j["scene_mesh"]["completeness"].get<double>(), 0.999);
  EXPECT_LT(j["scene_mesh"]["mean_completeness_m"].get<double>(), 1e-3);
  EXPECT_GT(j["scene_mesh"]["truth_samples"].get<int>(), 1000);
  EXPECT_LT(j["exact_depth"]["rmse_m"].get<double>(), 0.01);
}

}  // namespace
}  // namespace semap::tools
