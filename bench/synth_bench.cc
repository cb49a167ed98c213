// Speed of the synthetic sequence generator's stages (one core each): scene build, camera render, scan.
#include <benchmark/benchmark.h>

#include "engine/sim/synthetic_sequence.h"

namespace {

using namespace semap::sim;

SynthOptions Options(ScenePreset preset) {
  SynthOptions o;
  o.preset = preset;
  o.num_frames = 100;
  o.seed = 1;
  return o;
}

const SyntheticSequence& Sequence(ScenePreset preset) {
  static const SyntheticSequence urban(Options(ScenePreset::kUrban));
  static const SyntheticSequence vegetated(Options(ScenePreset::kVegetated));
  return preset == ScenePreset::kUrban ? urban : vegetated;
}

void BM_BuildSequence(benchmark::State& state) {
  const auto preset = static_cast<ScenePreset>(state.range(0));
  for (auto _ : state) {
    const SyntheticSequence s(Options(preset));
    benchmark::DoNotOptimize(s.scene().num_triangles());
    state.counters["triangles"] = static_cast<double>(s.scene().num_triangles());
  }
}
BENCHMARK(BM_BuildSequence)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_RenderCamera(benchmark::State& state) {
  const auto& s = Sequence(static_cast<ScenePreset>(state.range(0)));
  const CameraRenderer renderer(s.scene(), s.options());
  int frame = 0;
  for (auto _ : state) {
    auto img = renderer.Render(s.rig().calibration, s.scene_from_cam2(frame), {1.0, 7});
    benchmark::DoNotOptimize(img.color.data);
    frame = (frame + 7) % s.num_frames();
  }
}
BENCHMARK(BM_RenderCamera)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_RenderGeometry(benchmark::State& state) {
  const auto& s = Sequence(static_cast<ScenePreset>(state.range(0)));
  const CameraRenderer renderer(s.scene(), s.options());
  int frame = 0;
  for (auto _ : state) {
    auto img = renderer.RenderGeometry(s.rig().calibration, s.scene_from_cam2(frame));
    benchmark::DoNotOptimize(img.depth_m.data);
    frame = (frame + 7) % s.num_frames();
  }
}
BENCHMARK(BM_RenderGeometry)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_LidarScan(benchmark::State& state) {
  const auto& s = Sequence(static_cast<ScenePreset>(state.range(0)));
  const LidarScanner scanner(s.scene(), s.bvh(), s.options());
  int frame = 0;
  for (auto _ : state) {
    auto scan = scanner.Scan(s.scene_from_velo(frame), 3);
    benchmark::DoNotOptimize(scan.points_velo.data());
    state.counters["points"] = static_cast<double>(scan.points_velo.size());
    frame = (frame + 7) % s.num_frames();
  }
}
BENCHMARK(BM_LidarScan)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
