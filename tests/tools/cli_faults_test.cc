// Failures that looked like success, end to end through the `semap` executable: each must be an
// error naming what is wrong, with a non-zero exit code.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::RunSemap;

TEST(SemapCli, UnknownSubcommandIsNamedWithTheValidOnes) {
  const auto r = RunSemap("frobnicate x");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(r.Has("unknown subcommand 'frobnicate'")) << r.output;
  EXPECT_TRUE(r.Has("run, map-sfm, config")) << r.output;
}

TEST(SemapCli, ConfigPrintsTheShortestExactFormOfNumbers) {
  const auto r = RunSemap("config --set map.sigma_free_m=0.3");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("  sigma_free_m: 0.3\n")) << r.output;
  EXPECT_FALSE(r.Has("0.2999999")) << r.output;
  EXPECT_FALSE(r.Has("0.1000000")) << r.output;
}

TEST(SemapCli, NonFiniteConfigValuesAreRefusedNamingTheKey) {
  const fs::path dir = test::TempDir();
  test::WriteTextFile(dir / "c.yaml", "depth:\n  max_depth_m: .inf\n");
  const auto r = RunSemap("config --config " + (dir / "c.yaml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(r.Has("depth.max_depth_m")) << r.output;
  EXPECT_TRUE(r.Has("must be a finite number")) << r.output;
}

TEST(SemapEvalFaults, AMeshWithNoFacesIsAnErrorNotRmseZero) {
  const fs::path dir = test::TempDir();
  const test::TinyRaw t = test::WriteTinyRaw(dir / "raw");
  test::WriteTextFile(dir / "empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  const auto r = RunSemap("eval " + t.root.string() + " --mesh " + (dir / "empty.off").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has((dir / "empty.off").string() + ": mesh has no faces")) << r.output;
  EXPECT_FALSE(r.Has("RMSE")) << r.output;
}

TEST(SemapEvalFaults, AJsonFileThatCannotBeWrittenIsAnErrorNamingIt) {
  const fs::path dir = test::TempDir();
  const test::TinyRaw t = test::WriteTinyRaw(dir / "raw");
  // One triangle in front of the cameras.
  test::WriteTextFile(dir / "mesh.off", "OFF\n3 1 0\n-5 -5 10\n5 -5 10\n0 5 10\n3 0 1 2\n");
  for (const std::string target : {"/proc/semap_eval.json", "/dev/full"}) {
    const auto r =
        RunSemap("eval " + t.root.string() + " --mesh " + (dir / "mesh.off").string() + " --json " + target);
    EXPECT_EQ(r.exit_code, 1) << target << "\n" << r.output;
    EXPECT_TRUE(r.Has(target + ": ")) << target << "\n" << r.output;
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

}  // namespace
}  // namespace semap::tools
