// A split run over real UDP multicast, as users start it: `semap map` listening, then two depth nodes
// (`semap run --publish-depth --share 0/2` and `1/2`) playing a generated street at its 10 Hz, all three in
// a private network namespace (unshare -n) whose loopback carries the multicast route. The map node's
// mesh.ply equals that of `semap run` on the same frames in one process, byte for byte, and its summary
// accounts for every frame.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 12;

TEST(SplitRunOverLcm, TwoDepthNodesAndAMapNodeMapWhatOneProcessMaps) {
  if (test::RunShell("unshare -n true").exit_code != 0 || test::RunShell("which ip").exit_code != 0) {
    if (test::UnderCi()) FAIL() << "unshare -n and ip are needed under CI (scripts/setup installs them)";
    GTEST_SKIP() << "needs unshare -n (root) and iproute2";
  }
  const fs::path dir = test::TempDir();
  const auto at = [&](const std::string& name) { return (dir / name).string(); };
  const test::CliRun synth = test::RunSemap("synth --preset urban --frames " + std::to_string(kFrames) +
                                            " --seed 6 --out " + at("seq") + test::kSmallSynth);
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const test::CliRun single = test::RunSemap("run " + at("seq") + " --method PS --out " + at("single"));
  ASSERT_EQ(single.exit_code, 0) << single.output;

  const std::string exe = SEMAP_EXE;
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";
  const std::string node = " run " + at("seq") + " --method PS --publish-depth --realtime --lcm-url '" + url +
                           "' --set pipeline.depth_workers=1 --out ";
  // The map node first; the depth nodes once it listens; the map node ends split.idle_end_s after the last
  // datagram. `timeout` bounds the whole.
  const std::string script = "set -e; ip link set lo up; ip route add 224.0.0.0/4 dev lo; " + exe +
                             " map --method PS --lcm-url '" + url + "' --out " + at("map") +
                             " --set split.idle_end_s=2 >" + at("map.txt") + " 2>&1 & m=\\$!; sleep 0.5; " +
                             exe + node + at("a") + " --share 0/2 --node cam-a >" + at("a.txt") +
                             " 2>&1 & a=\\$!; " + exe + node + at("b") + " --share 1/2 --node cam-b >" +
                             at("b.txt") + " 2>&1 & b=\\$!; wait \\$a; wait \\$b; wait \\$m";
  const test::CliRun r = test::RunShell("timeout 120 unshare -n bash -c \"" + script + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.output << test::ReadFile(dir / "map.txt") << test::ReadFile(dir / "a.txt")
                            << test::ReadFile(dir / "b.txt");
  for (const char* n : {"a", "b"}) {
    const auto s = nlohmann::json::parse(std::ifstream(dir / n / "summary.json"));
    EXPECT_EQ(s["frames_integrated"].get<int>(), kFrames / 2) << n << ": " << s.dump();
    EXPECT_FALSE(fs::exists(dir / n / "mesh.ply")) << "a depth node writes no mesh";
  }
  const auto map = nlohmann::json::parse(std::ifstream(dir / "map" / "summary.json"));
  EXPECT_EQ(map["frames_integrated"].get<int>(), kFrames) << map.dump();
  EXPECT_EQ(map["frames_dropped"].get<int>(), 0) << map.dump();
  const std::string mesh = test::ReadFile(dir / "map" / "mesh.ply");
  EXPECT_FALSE(mesh.empty());
  EXPECT_EQ(mesh, test::ReadFile(dir / "single" / "mesh.ply"));
  EXPECT_NE(test::ReadFile(dir / "map.txt").find("12 received whole, 0 lost (0 announced"), std::string::npos)
      << test::ReadFile(dir / "map.txt");
}

}  // namespace
}  // namespace semap::tools
