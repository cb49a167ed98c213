// `semap view` on a finished run, loaded in headless Chromium: the page draws the mesh (a stated share of the
// screenshot's pixels differs from the background) and shows the run's triangle count (read from the PLY
// header, not through semap); a mesh file as source, coloured by label with its legend; the errors a user
// meets (port taken, no source, missing folder).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tests/tools/view_support.h"

namespace semap::tools {
namespace {

// The mesh must cover at least this share of the 3D view's pixels (panels hidden) after "fit to view": the
// 12-frame street below covers about 8 %; an empty or black canvas, or a mesh drawn off-screen, covers ~0.
constexpr double kMinShareDrawn = 0.05;

class View : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::TempDir());
    const std::string small =
        " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160 --set "
        "synth.cy_px=48"
        " --set synth.lidar_azimuth_steps=256";
    const auto synth = test::RunSemap("synth --preset urban --frames 12 --seed 3 --out " + At("seq") + small);
    ASSERT_EQ(synth.exit_code, 0) << synth.output;
    // The surface no view saw is kept (map.drop_unseen_surface=false) and every far point is inserted at once
    // (map.confirm_beyond_m=0), each vertex where its first sighting put it (map.fuse_gate_sigmas=0: fused
    // sightings make a smaller mesh of these 12 frames, 953 triangles): this tests the page, and a closed
    // street gives it the mesh the checks below were set on (over 1,000 triangles, ~8 % of the view drawn).
    const auto run = test::RunSemap("run " + At("seq") + " --out " + At("out") +
                                    " --set depth.max_points_per_frame=1500 --set pipeline.depth_workers=1"
                                    " --set map.drop_unseen_surface=false --set map.confirm_beyond_m=0"
                                    " --set map.fuse_gate_sigmas=0");
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override { ASSERT_TRUE(std::filesystem::exists(*dir_ / "out" / "mesh.ply")); }
  static std::string At(const char* name) { return (*dir_ / name).string(); }
  static inline std::filesystem::path* dir_ = nullptr;
};

TEST_F(View, PageDrawsTheFinishedRunAndShowsItsTriangleCount) {
  SEMAP_REQUIRE_BROWSER();
  const std::int64_t faces = test::PlyHeaderFaces(*dir_ / "out" / "mesh.ply");
  ASSERT_GT(faces, 1000);
  test::BackgroundView view(At("out") + " --port 0 --sequence " + At("seq") + " --seconds 300",
                            *dir_ / "view.txt");
  ASSERT_FALSE(view.url.empty()) << view.Log();
  const auto shot = *dir_ / "finished";
  std::filesystem::create_directories(shot);
  const auto r = test::RunShell(test::PageCheckCommand(view.url, shot) + " --expect-triangles " +
                                std::to_string(faces) + " --timeout-s 60");
  const auto report = test::PageReport(r.output);
  ASSERT_EQ(r.exit_code, 0) << r.output << view.Log();
  ASSERT_TRUE(report.is_object()) << r.output;
  EXPECT_EQ(report["triangles"].get<std::int64_t>(), faces) << r.output;
  EXPECT_EQ(report["meshes"].get<int>(), 1) << r.output;
  EXPECT_TRUE(report["has_error"].get<bool>())
      << "the generated sequence's scene_mesh.ply gives the error colouring";
  EXPECT_NE(report["status"].get<std::string>().find("12 camera poses"), std::string::npos) << r.output;
  EXPECT_TRUE(report["logs"].empty()) << r.output;  // no page error, no failed request
  const double share = test::ShareNotBackground(shot / "view.png");
  EXPECT_GE(share, kMinShareDrawn) << "share of the 3D view's pixels that differ from the background";
  std::printf(
      "mesh drawn on %.1f %% of the view's pixels (at least %.0f %% required); page loaded in %.1f s\n",
      100 * share, 100 * kMinShareDrawn, report["elapsed_s"].get<double>());
}

TEST_F(View, MeshFileColouredByLabelWithItsLegend) {
  SEMAP_REQUIRE_BROWSER();
  const auto ply = *dir_ / "out" / "mesh.ply";
  test::BackgroundView view(ply.string() + " --port 0 --seconds 300", *dir_ / "view_ply.txt");
  ASSERT_FALSE(view.url.empty()) << view.Log();
  const auto shot = *dir_ / "label";
  std::filesystem::create_directories(shot);
  const auto r = test::RunShell(test::PageCheckCommand(view.url + "?colour=label", shot) + " --expect-ply " +
                                ply.string() + " --timeout-s 60");
  const auto report = test::PageReport(r.output);
  ASSERT_EQ(r.exit_code, 0) << r.output << view.Log();
  EXPECT_EQ(report["triangles"].get<std::int64_t>(), test::PlyHeaderFaces(ply));
  EXPECT_FALSE(report["has_error"].get<bool>()) << "no true surface given";
  // The generated street's classes, named in the legend with their share of the vertices.
  const std::string legend = report["legend"].get<std::string>();
  EXPECT_NE(legend.find("Road"), std::string::npos) << legend;
  EXPECT_NE(legend.find("Building"), std::string::npos) << legend;
  EXPECT_GE(test::ShareNotBackground(shot / "view.png"), kMinShareDrawn);
}

TEST_F(View, TakenPortIsAClearError) {
  // Hold a port, as another server would.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  ASSERT_EQ(listen(fd, 1), 0);
  socklen_t len = sizeof(addr);
  ASSERT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  const int port = ntohs(addr.sin_port);
  const auto r = test::RunSemap("view " + At("out") + " --port " + std::to_string(port) + " --seconds 5");
  close(fd);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("semap view: port " + std::to_string(port) + " on 127.0.0.1 is already in use"))
      << r.output;
  EXPECT_TRUE(r.Has("--port")) << r.output;    // says what to do
  EXPECT_FALSE(r.Has("http://")) << r.output;  // no URL printed for a server that does not run
}

TEST_F(View, MissingSourceAndNoSourceAreClearErrors) {
  const auto missing = test::RunSemap("view " + At("no_such_run") + " --port 0 --seconds 5");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_TRUE(missing.Has("no_such_run")) << missing.output;
  EXPECT_TRUE(missing.Has("no such run folder or mesh file")) << missing.output;
  const auto none = test::RunSemap("view --port 0 --seconds 5");
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_TRUE(none.Has("give either a SOURCE")) << none.output;
  const auto seq_not_run = test::RunSemap("view " + At("seq") + " --port 0 --seconds 5");
  EXPECT_EQ(seq_not_run.exit_code, 1) << seq_not_run.output;
  EXPECT_TRUE(seq_not_run.Has("not a `semap run` output folder")) << seq_not_run.output;
}

}  // namespace
}  // namespace semap::tools
