// `semap map-sfm` run as a user would, end to end: a street whose surfaces are known exactly (ground, two
// walls, a parked car) is sampled into an SfM reconstruction, written in each input format, mapped in batch
// and incremental mode, and the mesh's distance to the true surfaces is measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>

#include "io/mesh/ply_off.h"
#include "io/sfm/colmap.h"
#include "io/sfm/openmvg.h"
#include "io/sfm/slam_json.h"
#include "tests/common/test_data.h"
#include "tests/engine/map/manifold_checker.h"
#include "tests/engine/map/map_test_util.h"
#include "tests/io/sfm/sfm_street.h"
#include "tests/io/sfm/sfm_test_util.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

// 25 keyframes 1 m apart, 300 new points each with 1 cm noise, observed again by up to 10 later keyframes.
test::SfmStreetOptions StreetOptions() {
  test::SfmStreetOptions o;
  o.keyframes = 25;
  o.new_points_per_keyframe = 300;
  o.noise_m = 0.01;
  return o;
}

struct Accuracy {
  test::SurfaceError surface;  // mesh samples → nearest true surface
  std::size_t rays = 0;        // pixel rays of the keyframes with a true surface within range
  std::size_t hits = 0;        // of those, rays that hit the mesh
  double depth_median_m = 0.0, depth_p75_m = 0.0, depth_p90_m = 0.0;
  double in_front_share = 0.0;  // hits more than 0.5 m in front of the true surface
};

std::ostream& operator<<(std::ostream& os, const Accuracy& a) {
  return os << "surface distance: mean " << a.surface.mean_m << " m, median " << a.surface.median_m
            << " m, rmse " << a.surface.rmse_m << " m, max " << a.surface.max_m << " m; rays: " << a.hits
            << " of " << a.rays << " hit the mesh, |depth error| median " << a.depth_median_m << " m, p75 "
            << a.depth_p75_m << " m, p90 " << a.depth_p90_m << " m, " << 100.0 * a.in_front_share
            << " % more than 0.5 m in front";
}

// Mesh accuracy against the exact street: distance of triangle samples to the surfaces, and depth along a
// grid of pixel rays from every keyframe (both sides measured along the same ray, as the map tests do).
Accuracy Measure(const Mesh& mesh, const test::StreetScene& scene, const io::SfmReconstruction& r,
                 double max_range_m) {
  Accuracy a;
  a.surface = test::MeshError(mesh, [&](const Eigen::Vector3d& p) { return scene.Distance(p); });
  std::vector<double> errors;
  std::size_t in_front = 0;
  for (std::size_t v = 0; v < r.views.size(); ++v) {
    const Pose3d& world_from_cam = r.views[v].world_from_cam;
    for (int j = 0; j < 8; ++j) {
      for (int i = 0; i < 12; ++i) {
        const Eigen::Vector3d dir =
            world_from_cam.linear() *
            Eigen::Vector3d((i + 0.37) / 12 * 1.6 - 0.8, (j + 0.41) / 8 * 1.0 - 0.5, 1.0).normalized();
        const auto truth = scene.Cast(world_from_cam.translation(), dir);
        if (!truth || truth->first > max_range_m - 5.0) continue;
        ++a.rays;
        const auto depth = test::RayMeshDistance(mesh, world_from_cam.translation(), dir);
        if (!depth) continue;
        ++a.hits;
        errors.push_back(std::abs(*depth - truth->first));
        in_front += *depth < truth->first - 0.5;
      }
    }
  }
  if (!errors.empty()) {
    std::sort(errors.begin(), errors.end());
    a.depth_median_m = errors[errors.size() / 2];
    a.depth_p75_m = errors[errors.size() * 3 / 4];
    a.depth_p90_m = errors[errors.size() * 9 / 10];
    a.in_front_share = double(in_front) / double(errors.size());
  }
  return a;
}

// Writes `r` in `format` under `dir`; returns the INPUT argument of map-sfm.
std::filesystem::path WriteInput(const io::SfmReconstruction& r, const std::string& format,
                                 const std::filesystem::path& dir) {
  if (format == "colmap") {
    io::WriteColmapModel(dir / "colmap_text", r, io::ColmapEncoding::kText);
    return dir / "colmap_text";
  }
  if (format == "colmap-bin") {
    io::WriteColmapModel(dir / "colmap_bin", r, io::ColmapEncoding::kBinary);
    return dir / "colmap_bin";
  }
  if (format == "openmvg") {
    io::WriteOpenMvgJson(dir / "sfm_data.json", r);
    return dir / "sfm_data.json";
  }
  io::WriteSlamJson(dir / "slam.json", r);
  return dir / "slam.json";
}

std::size_t CountLines(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// Measured (25 keyframes, 7 500 points with 1 cm noise, about 3 observations per point; map with the
// carve-and-repair extraction), batch and incremental alike: surface distance median 5 mm, mean 0.04 m; 99.7
// % of the rays hit the mesh, depth error median 1.4 cm, p90 5 cm, 2 % of the rays more than 0.5 m in front
// (PS-simplified input: mean 0.05 m, 2.4 %). The bounds are these measurements with a margin, not targets.
void ExpectAccurate(const Accuracy& a, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_LT(a.surface.median_m, 0.02);
  EXPECT_LT(a.surface.mean_m, 0.08);
  EXPECT_GT(a.rays, 1000u);
  EXPECT_GT(a.hits, a.rays * 98 / 100);
  EXPECT_LT(a.depth_median_m, 0.05);
  EXPECT_LT(a.depth_p90_m, 0.2);
  EXPECT_LT(a.in_front_share, 0.05);
}

TEST(SemapMapSfm, EveryFormatGivesAManifoldMeshOnTheTrueSurfaces) {
  const test::SfmStreetOptions o = StreetOptions();
  const test::StreetScene scene = test::SfmStreetScene(o);
  const io::SfmReconstruction r = test::MakeSfmStreet(scene, o);
  const auto dir = test::TempDir();
  std::vector<std::size_t> triangles;
  for (const std::string format : {"colmap", "colmap-bin", "openmvg", "slam-json"}) {
    SCOPED_TRACE(format);
    const auto input = WriteInput(r, format, dir);
    const auto out = dir / ("out_" + format);
    const std::string cli_format = format == "colmap-bin" ? "colmap" : format;
    const auto run = test::RunSemap("map-sfm " + input.string() + " --format " + cli_format +
                                    " --method O --out " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(run.Has("25 views, 7500 points")) << run.output;
    const Mesh mesh = io::ReadMeshPly(out / "mesh.ply");
    EXPECT_EQ(io::ReadMeshOff(out / "mesh.off").num_triangles(), mesh.num_triangles());
    EXPECT_EQ(CountLines(out / "frames.csv"), 2u);  // header + the one batch "frame"
    const auto report = test::CheckManifold(mesh, /*allow_boundary=*/true);
    EXPECT_TRUE(report.ok()) << report.Summary();
    const Accuracy a = Measure(mesh, scene, r, o.max_range_m);
    std::cout << format << " batch: " << mesh.num_triangles() << " triangles; " << a << "\n";
    ExpectAccurate(a, format + " batch");
    triangles.push_back(mesh.num_triangles());
  }
  // The same reconstruction whatever the format. The JSON formats store the rotation and centre as they
  // are: the same mesh; COLMAP's quaternion and translation move the centres by ~1e-15 m, which changes a
  // few triangles (9 of 14 740 measured).
  ASSERT_EQ(triangles.size(), 4u);
  EXPECT_EQ(triangles[0], triangles[1]);  // COLMAP text and binary
  EXPECT_EQ(triangles[2], triangles[3]);  // OpenMVG and SLAM JSON
  EXPECT_NEAR(double(triangles[0]), double(triangles[2]), 0.005 * double(triangles[2]));
}

// Runs the incremental map on the street (SLAM JSON input), publishing over LCM into a log file.
struct IncrementalRun {
  test::SfmStreetOptions options = StreetOptions();
  test::StreetScene scene = test::SfmStreetScene(options);
  io::SfmReconstruction reconstruction = test::MakeSfmStreet(scene, options);
  std::filesystem::path dir = test::TempDir();
  test::CliRun run;
  Mesh mesh;

  IncrementalRun() {
    const auto input = WriteInput(reconstruction, "slam-json", dir);
    run = test::RunSemap("map-sfm " + input.string() + " --format slam-json --incremental --method O --out " +
                         (dir / "inc").string() + " --lcm-url 'file://" + (dir / "run.lcmlog").string() +
                         "?mode=w'");
    if (run.exit_code == 0) mesh = io::ReadMeshPly(dir / "inc" / "mesh.ply");
  }
};

TEST(SemapMapSfm, IncrementalKeyframesGiveAManifoldMeshOnTheTrueSurfaces) {
  const IncrementalRun inc;
  ASSERT_EQ(inc.run.exit_code, 0) << inc.run.output;
  EXPECT_TRUE(inc.run.Has("25 keyframes")) << inc.run.output;
  EXPECT_EQ(CountLines(inc.dir / "inc" / "frames.csv"), 26u);  // header + one line per keyframe
  const auto report = test::CheckManifold(inc.mesh, /*allow_boundary=*/true);
  EXPECT_TRUE(report.ok()) << report.Summary();
  const Accuracy a = Measure(inc.mesh, inc.scene, inc.reconstruction, inc.options.max_range_m);
  std::cout << "slam-json incremental: " << inc.mesh.num_triangles() << " triangles; " << a << "\n";
  // Before the carve-and-repair extraction the incremental mesh lay in front of the surfaces here (depth
  // error median 7.6 m, 96 % of the rays more than 0.5 m short) while the batch map was right.
  ExpectAccurate(a, "incremental");

  // What went over LCM rebuilds the same mesh.
  const auto rebuilt = test::RunSemap("lcm-mesh " + (inc.dir / "run.lcmlog").string() + " --out " +
                                      (inc.dir / "lcm.ply").string());
  ASSERT_EQ(rebuilt.exit_code, 0) << rebuilt.output;
  EXPECT_EQ(io::ReadMeshPly(inc.dir / "lcm.ply").num_triangles(), inc.mesh.num_triangles());
}

TEST(SemapMapSfm, LabelledPointsAreSimplified) {
  const test::SfmStreetOptions o = StreetOptions();
  const test::StreetScene scene = test::SfmStreetScene(o);
  const io::SfmReconstruction r = test::MakeSfmStreet(scene, o);
  const auto dir = test::TempDir();
  const auto input = WriteInput(r, "openmvg", dir);
  const auto run =
      test::RunSemap("map-sfm " + input.string() + " --format openmvg --incremental --method PS --out " +
                     (dir / "ps").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(run.Has("simplification: method PS")) << run.output;
  const Mesh mesh = io::ReadMeshPly(dir / "ps" / "mesh.ply");
  EXPECT_FALSE(mesh.labels.empty());
  const std::size_t points_in_mesh = mesh.num_vertices();
  EXPECT_LT(points_in_mesh, r.num_points() * 9 / 10);  // road and walls thinned out
  const Accuracy a = Measure(mesh, scene, r, o.max_range_m);
  std::cout << "openmvg incremental PS: " << mesh.num_vertices() << " vertices, " << mesh.num_triangles()
            << " triangles; " << a << "\n";
  ExpectAccurate(a, "incremental PS");
}

TEST(SemapMapSfm, BadInputAndUsageAreClearErrors) {
  const auto dir = test::TempDir();
  std::ofstream(dir / "slam.json") << R"({"slam_data_version": "0.3", "intrinsics": [], "views": [
      {"viewId": 1, "id_intrinsic": 0, "extrinsic": {}, "observations": []}]})";
  const auto bad = test::RunSemap("map-sfm " + (dir / "slam.json").string() + " --format slam-json --out " +
                                  (dir / "o").string());
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_TRUE(bad.Has("slam.json: views[0] (viewId 1): id_intrinsic: intrinsic 0 does not exist"))
      << bad.output;

  const auto missing = test::RunSemap("map-sfm " + (dir / "nowhere").string() + " --format colmap");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_TRUE(missing.Has("nowhere: COLMAP model folder not found")) << missing.output;

  const auto format = test::RunSemap("map-sfm " + (dir / "slam.json").string() + " --format bundler");
  EXPECT_EQ(format.exit_code, 2) << format.output;
  EXPECT_TRUE(format.Has("bundler")) << format.output;

  const auto no_format = test::RunSemap("map-sfm " + (dir / "slam.json").string());
  EXPECT_EQ(no_format.exit_code, 2) << no_format.output;

  std::ofstream(dir / "empty.json") << R"({"slam_data_version": "0.3", "intrinsics": [], "views": []})";
  const auto empty = test::RunSemap("map-sfm " + (dir / "empty.json").string() +
                                    " --format slam-json --out " + (dir / "o").string());
  EXPECT_EQ(empty.exit_code, 1) << empty.output;
  EXPECT_TRUE(empty.Has("no posed view")) << empty.output;
}

TEST(SemapMapSfm, APointFarAwayIsLeftOutWithAWarningNotAnAssertion) {
  // One point at 1e12 m (an outlier, or a unit mistake) is beyond what the map covers: it is dropped and
  // counted, the others are mapped. A camera that far is an error naming the view.
  const auto dir = test::TempDir();
  io::SfmReconstruction r = test::SmallStreet();
  r.points_world[5] = {1e12, 0.0, 0.0};
  io::WriteOpenMvgJson(dir / "sfm_data.json", r);
  const auto run = test::RunSemap("map-sfm " + (dir / "sfm_data.json").string() + " --format openmvg --out " +
                                  (dir / "o").string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(run.Has("1 point(s) with a coordinate beyond 1000000 m were left out (first: point id " +
                      std::to_string(r.point_ids[5]) + ")"))
      << run.output;
  EXPECT_GT(io::ReadMeshPly(dir / "o" / "mesh.ply").num_triangles(), 0u);

  r.points_world[5] = {0.0, 0.0, 0.0};
  r.views[1].world_from_cam.translation().z() = -1e12;
  io::WriteOpenMvgJson(dir / "sfm_data.json", r);
  const auto camera = test::RunSemap("map-sfm " + (dir / "sfm_data.json").string() +
                                     " --format openmvg --out " + (dir / "o").string());
  EXPECT_EQ(camera.exit_code, 1) << camera.output;
  EXPECT_TRUE(camera.Has("view " + std::to_string(r.views[1].id))) << camera.output;
  EXPECT_TRUE(camera.Has("has its centre beyond 1000000 m")) << camera.output;
}

}  // namespace
}  // namespace semap::tools
