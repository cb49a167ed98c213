// No sky in the map on real frames: KITTI odometry 04 with ENet labels. ENet calls a good part of the
// upper image sky, and SGBM matches some of it; with semantics.drop_sky (the default) none of it reaches the
// map, so no vertex of `semap run`'s mesh carries the sky label.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/pipeline/semap_stages.h"
#include "io/frame_source.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

constexpr Label kSky = 11;  // Cityscapes

fs::path EnetModel() { return test::SharedDir() / "models/enet-cityscapes/enet-model.net"; }

TEST(SkyKittiOdometry04, SkyPixelsGivePointsOnlyWhenAsked) {
  SEMAP_REQUIRE_SHARED("data/kitti_odometry_04");
  SEMAP_REQUIRE_SHARED("models/enet-cityscapes/enet-model.net");
  io::FrameSourceOptions input;
  input.max_frames = 1;
  input.load_velodyne = false;
  const auto frame = io::OpenFrameSource(test::SharedDir() / "data/kitti_odometry_04", input)->Next();
  ASSERT_TRUE(frame.has_value());
  SemanticsOptions semantics;
  semantics.source = LabelSource::kEnet;
  semantics.enet_model_path = EnetModel().string();
  DepthOptions depth;
  depth.half_resolution = true;
  depth.max_points_per_frame = 0;
  semantics.drop_sky = false;
  const LabelledCloud with_sky =
      StereoLabelStage(depth, semantics, ClassMap::Cityscapes()).Process(*frame, nullptr);
  std::size_t sky = 0;
  for (Label l : with_sky.labels) sky += l == kSky ? 1 : 0;
  RecordProperty("sky_points_without_drop", std::to_string(sky));
  ASSERT_GT(sky, 100u) << "ENet + SGBM give sky points on this frame: the test below would prove nothing";

  semantics.drop_sky = true;
  const LabelledCloud without =
      StereoLabelStage(depth, semantics, ClassMap::Cityscapes()).Process(*frame, nullptr);
  EXPECT_EQ(without.size(), with_sky.size() - sky);
  for (Label l : without.labels) ASSERT_NE(l, kSky);
}

TEST(SkyKittiOdometry04, NoMeshVertexIsSky) {
  SEMAP_REQUIRE_SHARED("data/kitti_odometry_04");
  SEMAP_REQUIRE_SHARED("models/enet-cityscapes/enet-model.net");
  const fs::path out = test::TempDir() / "run";
  const CliRun r = RunSemap("run " + (test::SharedDir() / "data/kitti_odometry_04").string() +
                            " --method PS --frames 4 --progress-interval 100 --set semantics.source=enet"
                            " --set semantics.enet_model_path=" +
                            EnetModel().string() + " --set depth.half_resolution=true --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Mesh mesh = io::ReadMeshPly(out / "mesh.ply");
  ASSERT_GT(mesh.num_vertices(), 1000u);
  ASSERT_EQ(mesh.labels.size(), mesh.num_vertices());
  std::size_t sky = 0;
  for (Label l : mesh.labels) sky += l == kSky ? 1 : 0;
  EXPECT_EQ(sky, 0u);
}

}  // namespace
}  // namespace semap::tools
