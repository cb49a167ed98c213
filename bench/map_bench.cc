// Delaunay map benchmarks: batch build rates, and an incremental 500-frame drive with the memory bound on
// (time per frame vs map size). Run: ./build/bench/map_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cstdio>
#include <ctime>

#include "engine/core/mesh_delta.h"
#include "engine/map/batch_map.h"
#include "engine/map/incremental_map.h"
#include "tests/engine/map/street_scene.h"

namespace semap {
namespace {

// Thread CPU time: the development machine is shared, so wall time per frame mostly measures the load.
double ThreadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Pixel rays per drive frame (≈ 700 points per frame after range and sky).
constexpr int kDriveRaysX = 40, kDriveRaysZ = 24;

test::StreetScene LongStreet() {
  test::StreetScene scene;
  scene.length_m = 700.0;
  return scene;
}

LabelledCloud StreetFrame(const test::StreetScene& scene, int frame, int rays_x, int rays_z) {
  test::StreetSamplingOptions so;
  so.num_cameras = 1;
  so.first_camera_y_m = double(frame);  // 1 m per frame (KITTI at 10 Hz, 36 km/h)
  so.rays_x = rays_x;
  so.rays_z = rays_z;
  so.noise_m = 0.01;
  so.seed = unsigned(frame + 1);
  return test::SampleStreet(scene, so);
}

// Batch map of `state.range(0)` camera frames of the street (≈ 2000 points per frame).
void BM_BatchMap(benchmark::State& state) {
  const test::StreetScene scene = LongStreet();
  LabelledCloud cloud;
  for (int f = 0; f < state.range(0); ++f) cloud.Append(StreetFrame(scene, f, 60, 40));
  MapStatistics stats;
  for (auto _ : state) {
    const BatchMapResult r = BuildBatchMap(MapOptions(), cloud, {});
    stats = r.statistics;
    benchmark::DoNotOptimize(r.mesh.triangles.data());
  }
  state.counters["points"] = double(cloud.size());
  state.counters["points/s"] =
      benchmark::Counter(double(cloud.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rays/s"] =
      benchmark::Counter(double(stats.rays_traced), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["cells/ray"] = double(stats.cells_visited) / double(stats.rays_traced);
  state.counters["cells"] = double(stats.num_cells);
}
BENCHMARK(BM_BatchMap)->Arg(1)->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond);

// 500 frames of ≈ 700 points each through the incremental map, finalising points older than 20 frames.
// Reports the mean update CPU time of each 100-frame block (must stay flat) and the live map size.
void BM_IncrementalDrive(benchmark::State& state) {
  const test::StreetScene scene = LongStreet();
  const int frames = int(state.range(0));
  std::vector<LabelledCloud> input;
  for (int f = 0; f < frames; ++f) input.push_back(StreetFrame(scene, f, kDriveRaysX, kDriveRaysZ));
  MapOptions options;
  options.visibility = Visibility::kRays;  // point clouds without depth maps
  options.finalise_age_frames = 20;
  for (auto _ : state) {
    IncrementalMap map(options);
    MeshDiffer differ;
    std::vector<double> block_s(std::size_t((frames + 99) / 100), 0.0);
    std::size_t points = 0, rays_new = 0, rays_retraced = 0;
    double update_s = 0.0, extract_s = 0.0;
    for (int f = 0; f < frames; ++f) {
      const double t0 = ThreadCpuSeconds();
      const MapUpdateResult r = map.Update(input[std::size_t(f)]);
      const double t1 = ThreadCpuSeconds();
      const MeshDelta delta = differ.Update(f, map.ExtractIdentifiedMesh(), map.TakeFinalisedMesh());
      benchmark::DoNotOptimize(delta.added_triangles.data());
      const double t2 = ThreadCpuSeconds();
      const double dt = t1 - t0;
      update_s += dt;
      extract_s += t2 - t1;
      block_s[std::size_t(f / 100)] += dt;
      points += input[std::size_t(f)].size();
      rays_new += r.rays_traced;
      rays_retraced += r.rays_retraced;
      if (f % 50 == 49) {
        const MapStatistics s = map.Statistics();
        std::fprintf(stderr, "frame %4d: update %.1f ms CPU, live points %zu, cells %zu, rays %zu\n", f + 1,
                     1e3 * dt, s.num_points, s.num_cells, s.num_rays);
      }
    }
    const MapStatistics s = map.Statistics();
    for (std::size_t b = 0; b < block_s.size(); ++b) {
      state.counters["ms/frame_" + std::to_string(b * 100) + "+"] = 1e3 * block_s[b] / 100.0;
    }
    state.counters["ms/frame"] = 1e3 * update_s / frames;
    state.counters["delta_ms/frame"] = 1e3 * extract_s / frames;
    state.counters["points/s"] = double(points) / update_s;
    state.counters["rays/s"] = double(s.rays_traced) / update_s;
    state.counters["cells/ray"] = double(s.cells_visited) / double(s.rays_traced);
    state.counters["retraced/frame"] = double(rays_retraced) / frames;
    state.counters["new_rays/frame"] = double(rays_new) / frames;
    state.counters["live_cells"] = double(s.num_cells);
    state.counters["live_points"] = double(s.num_points);
  }
}
BENCHMARK(BM_IncrementalDrive)->Arg(500)->Iterations(1)->Unit(benchmark::kSecond);

// Full mesh extraction of a live map of 20 frames.
void BM_MeshExtraction(benchmark::State& state) {
  const test::StreetScene scene = LongStreet();
  MapOptions options;
  options.visibility = Visibility::kRays;  // point clouds without depth maps
  IncrementalMap map(options);
  for (int f = 0; f < 20; ++f) map.Update(StreetFrame(scene, f, 60, 40));
  std::size_t triangles = 0;
  for (auto _ : state) {
    const Mesh mesh = map.ExtractMesh();
    triangles = mesh.num_triangles();
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  state.counters["triangles"] = double(triangles);
  state.counters["cells"] = double(map.Statistics().num_cells);
}
BENCHMARK(BM_MeshExtraction)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace semap

BENCHMARK_MAIN();
