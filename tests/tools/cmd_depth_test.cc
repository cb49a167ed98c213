// `semap depth` run as a user would: on a real KITTI stereo-2015 frame, on a tiny generated raw sequence and
// on bad input.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/small_sequence.h"

namespace semap {
namespace {

constexpr const char* kSubset = "data/kitti_stereo2015_subset";

TEST(SemapDepth, RealFrameWritesDisparityPngsAndCloud) {
  SEMAP_REQUIRE_SHARED(kSubset);
  const auto out = test::TempDir() / "out";
  const auto r = test::RunSemap("depth " + (test::SharedDir() / kSubset).string() + " --frame 2 --out " +
                                out.string() + " --set depth.max_points_per_frame=0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat disparity = cv::imread((out / "disparity_000002.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(disparity.type(), CV_16UC1);
  EXPECT_EQ(disparity.size(), cv::Size(1242, 375));
  EXPECT_GT(cv::countNonZero(disparity), 0.8 * disparity.total());
  const cv::Mat colour = cv::imread((out / "disparity_colour_000002.png").string(), cv::IMREAD_COLOR);
  EXPECT_EQ(colour.size(), cv::Size(1242, 375));
  const LabelledCloud cloud = io::ReadCloudPly(out / "cloud_000002.ply");
  EXPECT_GT(cloud.size(), 200000u);
  ASSERT_EQ(cloud.labels.size(), cloud.size());
  for (const auto& p : cloud.positions_world) {
    ASSERT_TRUE(p.allFinite());
    ASSERT_GE(p.z(), 1.0 - 1e-3);
    ASSERT_LE(p.z(), 40.0 + 1e-3);
  }
  EXPECT_TRUE(r.Has("labels: none (all points unlabelled)")) << r.output;
}

TEST(SemapDepth, LabelsFromDiskColourThePoints) {
  const auto dir = test::TempDir();
  const auto t = test::WriteTinyRaw(dir / "raw", {.num_frames = 2, .width_px = 96, .height_px = 32});
  // The tiny sequence's gradient images have no texture to match: replace frame 1 by a textured plane at a
  // disparity of 8 px (fx 100 px, baseline 0.54 m: 6.75 m).
  cv::Mat noise(32, 96 + 8, CV_8UC3);
  cv::RNG(11).fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::imwrite((t.drive / "image_02/data/0000000001.png").string(), noise.colRange(0, 96));
  cv::imwrite((t.drive / "image_03/data/0000000001.png").string(), noise.colRange(8, 96 + 8));
  const auto out = dir / "out";
  const auto r = test::RunSemap("depth " + t.root.string() + " --frame 1 --out " + out.string() +
                                " --colour label --set depth.num_disparities=16 --set depth.block_size=3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out / "disparity_000001.png"));
  const LabelledCloud cloud = io::ReadCloudPly(out / "cloud_000001.ply");
  const ClassMap cityscapes = ClassMap::Cityscapes();
  ASSERT_GT(cloud.size(), 0u);
  ASSERT_EQ(cloud.labels.size(), cloud.size());
  // The tiny sequence's label images are half road, half building: both reach the points.
  const std::set<Label> present(cloud.labels.begin(), cloud.labels.end());
  EXPECT_TRUE(present.count(cityscapes.FindByName("Road"))) << r.output;
  EXPECT_TRUE(present.count(cityscapes.FindByName("Building"))) << r.output;
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.colors_rgb[i], cityscapes.Color(cloud.labels[i]));
  }
  EXPECT_TRUE(r.Has("labels: auto")) << r.output;
}

TEST(SemapDepth, BadInputGivesMessageAndExitCode) {
  const auto dir = test::TempDir();
  auto r = test::RunSemap("depth " + (dir / "missing").string() + " --frame 0 --out " + (dir / "o").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has("dataset folder not found")) << r.output;
  const auto t = test::WriteTinyRaw(dir / "raw", {.num_frames = 2});
  r = test::RunSemap("depth " + t.root.string() + " --frame 7 --out " + (dir / "o").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has("frame 7")) << r.output;
  r = test::RunSemap("depth " + t.root.string() + " --frame 0 --out " + (dir / "o").string() +
                     " --set depth.block_size=4");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.Has("depth.block_size")) << r.output;
  r = test::RunSemap("depth " + t.root.string() + " --frame 0 --out " + (dir / "o").string() +
                     " --colour pink");
  EXPECT_EQ(r.exit_code, 2);
  r = test::RunSemap(
      "depth " + t.root.string() + " --frame 0 --out " + (dir / "o").string() +
      " --set semantics.source=enet --set semantics.enet_model_path=" + (dir / "none.net").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has("none.net: file not found")) << r.output;
}

TEST(SemapDepth, AllFramesWritesDepthMapsPosesAndCameraForFusionTools) {
  const auto seq = test::SmallGeneratedSequence(3);
  const auto out = test::TempDir() / "all";
  const auto r = test::RunSemap("depth " + seq.string() + " --all --frames 2 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("depth maps: 2 frames (0 empty)")) << r.output;
  // camera.txt: the generated sequence's 480 x 144 camera.
  std::ifstream camera(out / "camera.txt");
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  camera >> width >> height >> fx >> fy >> cx >> cy;
  EXPECT_EQ(width, 480);
  EXPECT_EQ(height, 144);
  EXPECT_DOUBLE_EQ(cx, 240.0);
  EXPECT_GT(fx, 0.0);
  // poses.txt: one line per frame, its id and 12 numbers (the rotation part orthonormal).
  std::ifstream poses(out / "poses.txt");
  std::string line;
  int lines = 0;
  while (std::getline(poses, line)) {
    std::istringstream fields(line);
    long long id = -1;
    double m[12];
    fields >> id;
    for (double& v : m) fields >> v;
    ASSERT_TRUE(fields) << line;
    EXPECT_EQ(id, lines);
    const Eigen::Vector3d row0(m[0], m[1], m[2]);
    EXPECT_NEAR(row0.norm(), 1.0, 1e-9) << line;
    ++lines;
  }
  EXPECT_EQ(lines, 2);
  EXPECT_FALSE(std::filesystem::exists(out / "depth" / "000002.png"));
  // Each depth map (16-bit mm) agrees with the sequence's exact depth where both have one: SGBM's depth,
  // dense.
  for (const char* frame : {"000000.png", "000001.png"}) {
    const cv::Mat depth = cv::imread((out / "depth" / frame).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(depth.type(), CV_16UC1) << frame;
    ASSERT_EQ(depth.size(), cv::Size(480, 144));
    const cv::Mat exact = cv::imread(
        (seq / "2026_01_01" / "2026_01_01_drive_0001_sync" / "depth" / "data" / (std::string("0000") + frame))
            .string(),
        cv::IMREAD_UNCHANGED);
    ASSERT_EQ(exact.size(), depth.size()) << frame;
    int both = 0, close = 0;
    for (int y = 0; y < depth.rows; ++y) {
      for (int x = 0; x < depth.cols; ++x) {
        const double d = depth.at<std::uint16_t>(y, x), e = exact.at<std::uint16_t>(y, x);
        if (d == 0 || e == 0) continue;
        EXPECT_GE(d, 1000.0);   // depth.min_depth_m
        EXPECT_LE(d, 40000.0);  // depth.max_depth_m
        ++both;
        close += std::abs(d - e) < 0.05 * e ? 1 : 0;
      }
    }
    EXPECT_GT(both, 480 * 144 / 3) << frame;  // dense, not the map's 10,000-point budget
    EXPECT_GT(close, 0.8 * both) << frame;
  }
}

}  // namespace
}  // namespace semap
