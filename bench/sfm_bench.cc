// sfm_bench: writes the synthetic street reconstruction of the map-sfm tests (tests/io/sfm/sfm_street.h) in
// any input format of `semap map-sfm`, for benchmarking it (bench/sfm_bench.sh runs the three sizes).
//
// Usage: sfm_bench --out PATH [--format colmap-bin|colmap|openmvg|slam-json] [--keyframes 100]
//                  [--points 1000] [--track 10] [--noise 0.01] [--seed 1]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>

#include "io/sfm/colmap.h"
#include "io/sfm/openmvg.h"
#include "io/sfm/slam_json.h"
#include "tests/io/sfm/sfm_street.h"

int main(int argc, char** argv) {
  CLI::App app{"Write a synthetic SfM street reconstruction (keyframes along a street corridor)"};
  std::string out, format = "colmap-bin";
  semap::test::SfmStreetOptions o;
  o.keyframes = 100;
  o.new_points_per_keyframe = 1000;
  o.noise_m = 0.01;
  app.add_option("--out", out, "COLMAP model folder or JSON file")->required();
  app.add_option("--format", format, "colmap-bin | colmap | openmvg | slam-json")
      ->check(CLI::IsMember({"colmap-bin", "colmap", "openmvg", "slam-json"}))
      ->capture_default_str();
  app.add_option("--keyframes", o.keyframes, "keyframes (1 m apart)")->capture_default_str();
  app.add_option("--points", o.new_points_per_keyframe, "new points per keyframe")->capture_default_str();
  app.add_option("--track", o.max_track_keyframes, "later keyframes that may observe a point")
      ->capture_default_str();
  app.add_option("--noise", o.noise_m, "Gaussian noise on the point positions (m)")->capture_default_str();
  app.add_option("--seed", o.seed, "random seed")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const semap::io::SfmReconstruction r = semap::test::MakeSfmStreet(semap::test::SfmStreetScene(o), o);
    if (format == "colmap-bin") {
      semap::io::WriteColmapModel(out, r, semap::io::ColmapEncoding::kBinary);
    } else if (format == "colmap") {
      semap::io::WriteColmapModel(out, r, semap::io::ColmapEncoding::kText);
    } else if (format == "openmvg") {
      semap::io::WriteOpenMvgJson(out, r);
    } else {
      semap::io::WriteSlamJson(out, r);
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "%s (%s): %zu views, %zu points, %zu observations (%.2f per point, %.0f rays to earlier points "
        "per keyframe), %.1f s\n",
        out.c_str(), format.c_str(), r.views.size(), r.num_points(), r.observations.size(),
        double(r.observations.size()) / double(r.num_points()),
        double(r.observations.size() - r.num_points()) / double(r.views.size()), s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sfm_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
