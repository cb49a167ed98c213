// `semap simplify` run as a user would: a labelled cloud PLY in, per-class counts printed, the kept cloud
// out.
#include <gtest/gtest.h>

#include <random>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

constexpr Label kRoad = 1;
constexpr Label kCar = 14;

// A 20 × 20 m road plane sampled every 5 cm (noisy), a car box on it, one camera 1.5 m above the road.
LabelledCloud RoadAndCar() {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.005);
  LabelledCloud c;
  c.camera_centers_world = {{0.0, 0.0, 1.5}};
  c.camera_frame_ids = {0};
  auto add = [&](const Eigen::Vector3d& p, Label label) {
    c.positions_world.push_back(p);
    c.labels.push_back(label);
    c.camera_index.push_back(0);
  };
  for (double x = -10; x < 10; x += 0.05) {
    for (double y = 2; y < 22; y += 0.05) add({x, y, noise(rng)}, kRoad);
  }
  for (double x = -1; x < 1; x += 0.05) {
    for (double z = 0; z < 1.5; z += 0.05) add({x, 8.0, z}, kCar);  // the car's rear face
  }
  return c;
}

TEST(SemapSimplify, PrintsPerClassCountsAndWritesTheKeptCloud) {
  const auto dir = test::TempDir();
  const LabelledCloud in = RoadAndCar();
  io::WriteCloudPly(dir / "in.ply", in);
  const auto r = test::RunSemap("simplify " + (dir / "in.ply").string() + " --method PS --out " +
                                (dir / "out.ply").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("method PS")) << r.output;
  EXPECT_TRUE(r.Has("Road")) << r.output;
  EXPECT_TRUE(r.Has("Car")) << r.output;
  EXPECT_TRUE(r.Has("points/s")) << r.output;
  const LabelledCloud out = io::ReadCloudPly(dir / "out.ply");
  size_t road_in = 0, car_in = 0, road_out = 0, car_out = 0;
  for (auto l : in.labels) (l == kRoad ? road_in : car_in) += 1;
  for (auto l : out.labels) (l == kRoad ? road_out : car_out) += 1;
  EXPECT_EQ(car_out, car_in);          // cars are never simplified
  EXPECT_LT(road_out, road_in * 0.8);  // the road is
  EXPECT_GT(road_out, 0u);
}

TEST(SemapSimplify, BadMethodAndMissingFileAreClearErrors) {
  const auto dir = test::TempDir();
  io::WriteCloudPly(dir / "in.ply", RoadAndCar());
  const auto bad = test::RunSemap("simplify " + (dir / "in.ply").string() + " --method NOPE");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_TRUE(bad.Has("NOPE")) << bad.output;
  const auto missing = test::RunSemap("simplify " + (dir / "missing.ply").string());
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_TRUE(missing.Has("missing.ply")) << missing.output;
}

}  // namespace
}  // namespace semap::tools
