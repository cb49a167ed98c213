// `semap run --lcm-url` recorded by the real lcm-logger (liblcm-bin), then `semap lcm-mesh` rebuilds the mesh
// from the log: it must equal the mesh file the run wrote. Everything runs inside a private network namespace
// (unshare -n) whose loopback carries the multicast route, so no packet leaves the test.
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

std::multiset<std::array<float, 9>> Triangles(const Mesh& m) {
  std::multiset<std::array<float, 9>> out;
  for (const auto& t : m.triangles) {
    std::array<std::array<float, 3>, 3> v;
    for (int k = 0; k < 3; ++k) {
      const auto& p = m.vertices[t[k]];
      v[k] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
    }
    const int first = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());  // keep orientation
    std::array<float, 9> key;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) key[3 * k + c] = v[(first + k) % 3][c];
    }
    out.insert(key);
  }
  return out;
}

TEST(LcmLogger, LogOfARunRebuildsTheWrittenMesh) {
  if (test::RunShell("unshare -n true").exit_code != 0 || test::RunShell("which lcm-logger ip").exit_code != 0) {
    if (test::UnderCi()) FAIL() << "unshare -n, ip and lcm-logger are needed under CI (scripts/setup installs them)";
    GTEST_SKIP() << "needs unshare -n (root), iproute2 and lcm-logger";
  }
  const auto dir = test::TempDir();
  const std::string exe = SEMAP_EXE;
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";
  const std::string small =
      " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160 --set synth.cy_px=48"
      " --set synth.lidar_azimuth_steps=256";
  const auto synth = test::RunSemap("synth --preset urban --frames 4 --seed 3 --out " + (dir / "seq").string() + small);
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  // In the namespace: loopback up with the multicast route, logger in the background, the run, then stop the
  // logger (SIGINT lets it flush and close the log).
  // The logger is stopped whatever happens (trap), and its output goes to a file so that it never holds
  // the test's pipe open; `timeout` bounds the whole thing.
  const std::string script =
      "set -e; ip link set lo up; ip route add 224.0.0.0/4 dev lo; "
      // Room for a whole mesh message in the receiver's socket (UDP drops fragments that do not fit).
      "sysctl -q -w net.core.rmem_max=16777216 net.core.rmem_default=16777216 2>/dev/null || true; "
      "lcm-logger -q -f --lcm-url='" + url + "' " + (dir / "run.lcmlog").string() + " >" +
      (dir / "logger.txt").string() + " 2>&1 & logger=\\$!; trap 'kill -INT \\$logger; wait \\$logger' EXIT; "
      "sleep 0.5; " + exe + " run " + (dir / "seq").string() + " --out " + (dir / "out").string() +
      " --lcm-url '" + url + "' --set depth.max_points_per_frame=1500 --set pipeline.depth_workers=1; sleep 0.5";
  const auto run = test::RunShell("timeout 300 unshare -n bash -c \"" + script + "\"");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_TRUE(run.Has("LCM:")) << run.output;
  EXPECT_TRUE(run.Has("0 send failures")) << run.output;

  const auto replay = test::RunSemap("lcm-mesh " + (dir / "run.lcmlog").string() + " --out " +
                                     (dir / "replayed.ply").string());
  ASSERT_EQ(replay.exit_code, 0) << replay.output;  // non-zero if a message was lost
  const Mesh written = io::ReadMeshPly(dir / "out" / "mesh.ply");
  const Mesh replayed = io::ReadMeshPly(dir / "replayed.ply");
  ASSERT_GT(written.num_triangles(), 100u);
  EXPECT_EQ(replayed.num_triangles(), written.num_triangles());
  EXPECT_EQ(Triangles(replayed), Triangles(written));
}

}  // namespace
}  // namespace semap::tools
