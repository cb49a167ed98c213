// `semap render` as a user runs it: a known mesh written to PLY, the PNG read back and its pixels counted.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

// Pixels of the PNG above its legend strip (the bottom 30 rows) that are not white.
int NonWhiteAboveLegend(const cv::Mat& image) {
  int n = 0;
  for (int y = 0; y < image.rows - 30; ++y) {
    for (int x = 0; x < image.cols; ++x) n += image.at<cv::Vec3b>(y, x) != cv::Vec3b(255, 255, 255) ? 1 : 0;
  }
  return n;
}

// A 20 m × 10 m rectangle at height 1 (z-up) with a coloured quarter, and a 10 m wall standing on its edge.
Mesh RectangleAndWall() {
  Mesh m;
  m.vertices = {{0, 0, 1}, {20, 0, 1}, {20, 10, 1}, {0, 10, 1},
                {0, 0, 1}, {10, 0, 1}, {10, 0, 11}, {0, 0, 11}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  m.colors_rgb.assign(m.vertices.size(), {200, 30, 30});
  return m;
}

TEST(SemapRender, TopViewCoversTheMeshsShapeAndNothingElse) {
  const fs::path dir = test::TempDir();
  io::WriteMeshPly(dir / "m.ply", RectangleAndWall());
  const CliRun r = RunSemap("render " + (dir / "m.ply").string() +
                            " --up z --width 424 --height 1000 --out " + (dir / "top.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat image = cv::imread((dir / "top.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  // 20 m fitted into 424 − 2 × 12 = 400 px: 20 px/m; the rectangle is 400 × 200 px, the wall edge-on.
  EXPECT_EQ(image.cols, 424);
  EXPECT_EQ(image.rows, 200 + 24 + 30);
  EXPECT_EQ(NonWhiteAboveLegend(image), 400 * 200);
  EXPECT_TRUE(r.Has("80000 px covered")) << r.output;
  // Vertex colours (red), shaded: red dominates.
  const cv::Vec3b centre = image.at<cv::Vec3b>(12 + 100, 12 + 200);
  EXPECT_GT(centre[2], 2 * centre[1]);

  // From the side (elevation 10°, looking along +y) the wall is seen face on: more pixels than its edge.
  const CliRun side = RunSemap("render " + (dir / "m.ply").string() +
                               " --up z --elevation 10 --colour height --out " + (dir / "side.png").string());
  ASSERT_EQ(side.exit_code, 0) << side.output;
  EXPECT_FALSE(cv::imread((dir / "side.png").string()).empty());

  // Along −y (a camera frame's up) the rectangle is edge-on and the wall, 10 m × 10 m, is seen face on:
  // x spans 20 m in 1400 − 24 px (68.8 px/m), so the wall covers 688 × 688 px.
  const CliRun y_down =
      RunSemap("render " + (dir / "m.ply").string() + " --up=-y --out " + (dir / "y.png").string());
  ASSERT_EQ(y_down.exit_code, 0) << y_down.output;
  const cv::Mat wall = cv::imread((dir / "y.png").string());
  EXPECT_NEAR(NonWhiteAboveLegend(wall), 688 * 688, 2 * 688);
  // auto takes the thinnest axis of the bounding box (y and z tie at 10 m: y, as down): the same picture.
  const CliRun guess =
      RunSemap("render " + (dir / "m.ply").string() + " --out " + (dir / "auto.png").string());
  ASSERT_EQ(guess.exit_code, 0) << guess.output;
  cv::Mat difference;
  cv::absdiff(cv::imread((dir / "auto.png").string()), wall, difference);
  EXPECT_EQ(cv::countNonZero(difference.reshape(1)), 0);
}

TEST(SemapRender, ErrorColoursNeedATruthAndBadOptionsAreUsageErrors) {
  const fs::path dir = test::TempDir();
  io::WriteMeshPly(dir / "m.ply", RectangleAndWall());
  const CliRun no_truth =
      RunSemap("render " + (dir / "m.ply").string() + " --colour error --out " + (dir / "e.png").string());
  EXPECT_EQ(no_truth.exit_code, 2) << no_truth.output;
  EXPECT_TRUE(no_truth.Has("--truth")) << no_truth.output;

  // Against itself every pixel is within τ: green.
  const CliRun self = RunSemap("render " + (dir / "m.ply").string() + " --up z --colour error --truth " +
                               (dir / "m.ply").string() + " --out " + (dir / "e.png").string());
  ASSERT_EQ(self.exit_code, 0) << self.output;
  const cv::Mat image = cv::imread((dir / "e.png").string());
  const cv::Vec3b centre = image.at<cv::Vec3b>(image.rows / 3, image.cols / 2);
  EXPECT_GT(centre[1], centre[2]);
  EXPECT_GT(centre[1], centre[0]);

  EXPECT_EQ(RunSemap("render " + (dir / "m.ply").string() + " --up w --out x.png").exit_code, 2);
  const CliRun flat =
      RunSemap("render " + (dir / "m.ply").string() + " --elevation 0 --out " + (dir / "f.png").string());
  EXPECT_EQ(flat.exit_code, 2) << flat.output;
  EXPECT_TRUE(flat.Has("elevation_deg")) << flat.output;
  EXPECT_NE(RunSemap("render /nonexistent.ply --out " + (dir / "n.png").string()).exit_code, 0);
}

}  // namespace
}  // namespace semap::tools
