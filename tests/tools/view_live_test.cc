// The page of `semap view --lcm-url` follows a live `semap run --lcm-url` over real UDP multicast until it
// shows the run's final triangle count (the face count of the mesh.ply the run wrote, read from its header).
// Everything runs in a private network namespace (unshare -n) whose loopback carries the multicast route, as
// in lcm_logger_test.cc: no packet leaves the test. Label `network` (root for unshare, chromium, node).
#include <gtest/gtest.h>

#include <fstream>

#include "tests/tools/view_support.h"

namespace semap::tools {
namespace {

TEST(ViewLive, PageFollowsALiveRunToItsFinalTriangleCount) {
  if (test::RunShell("unshare -n true").exit_code != 0 || test::RunShell("command -v ip").exit_code != 0) {
    if (test::UnderCi()) FAIL() << "unshare -n (root) and ip are needed under CI";
    GTEST_SKIP() << "needs unshare -n (root) and iproute2";
  }
  SEMAP_REQUIRE_BROWSER();
  const auto dir = test::TempDir();
  const auto at = [&](const char* name) { return (dir / name).string(); };
  const std::string small =
      " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160 --set "
      "synth.cy_px=48"
      " --set synth.lidar_azimuth_steps=256";
  const auto synth = test::RunSemap("synth --preset urban --frames 20 --seed 3 --out " + at("seq") + small);
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const std::string exe = SEMAP_EXE;
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";
  // In the namespace: loopback up with the multicast route; the viewer; the page (page_check.mjs) until it is
  // connected; then the run (finalising early, so that finalised blocks are shown too; at the sequence's
  // 10 Hz, as a stream: flat out, its 20 small frames were over before the page had drawn three counts, 2
  // runs in 7); then wait for the page to reach the count of the run's mesh.ply. The viewer and the page are
  // stopped whatever happens.
  const std::string script =
      "set -eu\n"
      "ip link set lo up\n"
      "ip route add 224.0.0.0/4 dev lo\n" +
      exe + " view --lcm-url '" + url + "' --port 0 --seconds 280 > " + at("view.txt") +
      " 2>&1 & v=$!\n"
      "p=\n"
      "trap 'kill $v $p 2>/dev/null || true; wait $v 2>/dev/null || true' EXIT\n"
      "until grep -q '^http://' " +
      at("view.txt") +
      "; do kill -0 $v; sleep 0.05; done\n"
      "u=$(grep -m1 '^http://' " +
      at("view.txt") + ")\n" + test::PageCheckCommand("$u", dir) + " --expect-ply " + at("out/mesh.ply") +
      " --ready-file " + at("ready") + " --timeout-s 200 > " + at("page.txt") +
      " 2>&1 & p=$!\n"
      "until [ -e " +
      at("ready") + " ]; do kill -0 $p; sleep 0.05; done\n" + exe + " run " + at("seq") + " --out " +
      at("out") + " --lcm-url '" + url +
      "' --set depth.max_points_per_frame=1500 --set pipeline.depth_workers=1"
      " --set map.finalise_age_frames=3 --set map.finalise_min_age_frames=1 --set map.finalise_every_frames=2"
      // Every far point inserted at once, each vertex where its first sighting put it: the mesh the checks
      // below were set on (over 1,000 triangles); with far points waiting for confirmation this small street
      // has ~600; fused sightings and the votes by each point's σ make it smaller too (434 triangles), so it
      // keeps every surface triangle, seen or not (1,140 triangles).
      " --set map.confirm_beyond_m=0 --set map.fuse_gate_sigmas=0 --set map.drop_unseen_surface=false --mode "
      "realtime > " +
      at("run.txt") +
      " 2>&1\n"
      "status=0; wait $p || status=$?; p=\n"
      "echo page_check exit $status\n"
      "exit $status\n";
  std::ofstream(dir / "live.sh") << script;
  const auto r = test::RunShell("timeout 280 unshare -n bash " + at("live.sh"));
  const std::string page = test::ReadFile(dir / "page.txt");
  ASSERT_EQ(r.exit_code, 0) << r.output << page << test::ReadFile(dir / "run.txt")
                            << test::ReadFile(dir / "view.txt");
  const std::int64_t faces = test::PlyHeaderFaces(dir / "out" / "mesh.ply");
  ASSERT_GT(faces, 1000);
  const auto report = test::PageReport(page);
  ASSERT_TRUE(report.is_object()) << page;
  EXPECT_EQ(report["triangles"].get<std::int64_t>(), faces) << page;
  EXPECT_EQ(report["expected"].get<std::int64_t>(), faces) << page;
  // It followed the map as it grew: several counts before the final one.
  const auto seen = report["counts_seen"].get<std::vector<std::int64_t>>();
  EXPECT_GE(seen.size(), 3u) << page;
  EXPECT_EQ(seen.back(), faces) << page;
  EXPECT_NE(report["source"].get<std::string>().find("live: " + url), std::string::npos) << page;
  EXPECT_EQ(report["status"].get<std::string>().rfind("run ", 0), 0u) << page;  // names the run it follows
  EXPECT_TRUE(report["logs"].empty()) << page;
  EXPECT_GE(test::ShareNotBackground(dir / "view.png"), 0.02) << "the live map is drawn";
  std::printf("page followed the run through %zu triangle counts to %lld in %.1f s\n", seen.size(),
              static_cast<long long>(faces), report["elapsed_s"].get<double>());
}

}  // namespace
}  // namespace semap::tools
