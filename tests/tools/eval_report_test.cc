// `semap run --eval` and `semap eval --json` (tools/eval_report): per-frame accuracy files a user can plot.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/mesh/ply_off.h"
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

  // The by-area figures against the scene mesh, and the per-vertex one under its own name.
  const auto& scene = a["scene_mesh"];
  EXPECT_EQ(scene["area_samples"].get<int>(), 100000);
  EXPECT_GT(scene["area_m2"].get<double>(), 10.0);
  for (const char* share : {"accuracy", "area_within_near", "area_beyond_near", "area_beyond_far", "vertex_accuracy"}) {
    EXPECT_GE(scene[share].get<double>(), 0.0) << share;
    EXPECT_LE(scene[share].get<double>(), 1.0) << share;
  }
  EXPECT_LE(scene["accuracy"].get<double>(), scene["area_within_near"].get<double>());
  EXPECT_NEAR(scene["area_within_near"].get<double>() + scene["area_beyond_near"].get<double>(), 1.0, 1e-12);
  EXPECT_LE(scene["area_beyond_far"].get<double>(), scene["area_beyond_near"].get<double>());
  EXPECT_TRUE(run.Has("of the area within tau")) << run.output;
  // Its pictures from above.
  for (const char* png : {"top_view.png", "top_view_error.png"}) {
    const cv::Mat image = cv::imread((out / png).string());
    ASSERT_FALSE(image.empty()) << png;
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(grey < 250), image.total() / 20) << png;  // the mesh covers a good part of it
  }
}

TEST(SemapEval, TheExactSceneMeshIsAccurateAndComplete) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path json = test::TempDir() / "scene.json";
  const fs::path scene = seq / "2026_01_01" / "2026_01_01_drive_0001_sync" / "scene_mesh.ply";
  const fs::path pictures = test::TempDir() / "pictures";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + scene.string() + " --json " + json.string() +
                               " --pictures " + pictures.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(eval.Has("vs scene mesh accuracy 100.0 %")) << eval.output;
  const auto j = nlohmann::json::parse(std::ifstream(json));
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["accuracy"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["vertex_accuracy"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["area_beyond_far"].get<double>(), 0.0);
  EXPECT_LT(j["scene_mesh"]["mean_distance_m"].get<double>(), 1e-6);
  // Its area, summed here from the file.
  const Mesh truth = io::ReadMeshPly(scene);
  double area = 0.0;
  for (const auto& t : truth.triangles) {
    const Eigen::Vector3d a = truth.vertices[t[0]];
    area += 0.5 * (truth.vertices[t[1]] - a).cross(truth.vertices[t[2]] - a).norm();
  }
  EXPECT_NEAR(j["scene_mesh"]["area_m2"].get<double>(), area, 1e-9 * area);
  // The truth against itself, seen from above: every covered pixel in the green bin (G above R and B).
  const cv::Mat error = cv::imread((pictures / "top_view_error.png").string());
  ASSERT_FALSE(error.empty());
  int covered = 0, green = 0;
  for (int y = 0; y < error.rows - 30; ++y) {
    for (int x = 0; x < error.cols; ++x) {
      const cv::Vec3b c = error.at<cv::Vec3b>(y, x);
      if (c == cv::Vec3b(255, 255, 255) || (c[0] == c[1] && c[1] == c[2])) continue;  // background, track
      ++covered;
      green += c[1] > c[2] && c[1] > c[0] ? 1 : 0;
    }
  }
  EXPECT_GT(covered, 10000);
  EXPECT_GT(green, 0.99 * covered);
  // Truth samples come from the 16-bit millimetre depth PNGs: within a millimetre of the true surface.
  EXPECT_GT(j["scene_mesh"]["completeness"].get<double>(), 0.999);
  EXPECT_LT(j["scene_mesh"]["mean_completeness_m"].get<double>(), 1e-3);
  EXPECT_GT(j["scene_mesh"]["truth_samples"].get<int>(), 1000);
  EXPECT_LT(j["exact_depth"]["rmse_m"].get<double>(), 0.01);
}

}  // namespace
}  // namespace semap::tools
