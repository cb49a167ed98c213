// `semap run` with the plane sweep beside SGBM (plane_sweep.stereo_past_frames): the run's frames get the
// earlier frames' views and the map is built from the combined depth.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/engine/map/manifold_checker.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

TEST(StereoSweepRun, MapsTheCombinedDepthIntoA2Manifold) {
  const fs::path seq = test::SmallGeneratedSequence(6);
  const fs::path root = test::TempDir();
  const std::string common = "run " + seq.string() + " --method PS --progress-interval 0 ";
  const CliRun alone = RunSemap(common + "--out " + (root / "sgbm").string());
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  // This small, narrow street is near and its earlier frames see it with little parallax: the sweep serves
  // from 4 m, at half the pair's parallax.
  const std::string sweep_options =
      "--set plane_sweep.stereo_past_frames=2 --set plane_sweep.num_planes=32 "
      "--set plane_sweep.stereo_min_depth_m=4 --set plane_sweep.stereo_max_depth_m=40 "
      "--set plane_sweep.stereo_parallax_gain=0.5 ";
  const CliRun swept = RunSemap(common + sweep_options + "--out " + (root / "sweep").string());
  ASSERT_EQ(swept.exit_code, 0) << swept.output;
  const Mesh sgbm_mesh = io::ReadMeshPly(root / "sgbm" / "mesh.ply");
  const Mesh sweep_mesh = io::ReadMeshPly(root / "sweep" / "mesh.ply");
  ASSERT_GT(sweep_mesh.num_triangles(), 0u);
  const auto report = test::CheckManifold(sweep_mesh, /*allow_boundary=*/true);
  EXPECT_TRUE(report.ok()) << report.Summary();
  // The sweep's depth reached the map: its vertices are not SGBM's alone.
  EXPECT_FALSE(test::ReadFile(root / "sgbm" / "mesh.ply") == test::ReadFile(root / "sweep" / "mesh.ply"));
  EXPECT_GT(sgbm_mesh.num_triangles(), 0u);
}

}  // namespace
}  // namespace semap::tools
