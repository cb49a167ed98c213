// Depth stage micro-benchmarks on a real KITTI stereo-2015 frame (1242×375): SGBM disparity and the full
// stage (disparity + point cloud) at full and half resolution, on one core (cv::setNumThreads(1)). As in a
// stream, the pair's row offsets (depth.align_rows) are measured once, outside the timed loops (the reader
// of `semap run` measures them on the first frames, then every 100): BM_FitRowOffsets times that fit.
// Run: ./build/bench/depth_bench  (SEMAP_SHARED overrides the shared folder)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <string>

#include "engine/depth/row_alignment.h"
#include "engine/depth/stereo_depth.h"
#include "tests/common/kitti2015_subset.h"

namespace {

const semap::test::Stereo2015Frame& TestFrame() {
  static const semap::test::Stereo2015Frame frame = [] {
    const char* env = std::getenv("SEMAP_SHARED");
    const std::string shared = env ? env : std::string(SEMAP_SHARED_DIR);
    return semap::test::LoadStereo2015Frame(shared + "/data/kitti_stereo2015_subset", "000002_10");
  }();
  return frame;
}

// The test frame with its row offsets measured once, as the stream's reader attaches them (all zero when the
// fit finds nothing: measured, nothing to correct).
const semap::Frame& AlignedFrame() {
  static const semap::Frame frame = [] {
    semap::Frame f = TestFrame().frame;
    semap::RowOffsets none;
    none.image_size = f.left.size();
    f.row_offsets = semap::FitRowOffsets(f.left, f.right).value_or(none);
    return f;
  }();
  return frame;
}

void BM_Disparity(benchmark::State& state) {
  cv::setNumThreads(1);
  semap::DepthOptions o;
  o.half_resolution = state.range(0) != 0;
  const semap::StereoDepth depth(o);
  const semap::Frame& f = AlignedFrame();
  for (auto _ : state) benchmark::DoNotOptimize(depth.Compute(f.left, f.right, &*f.row_offsets));
  state.SetLabel(o.half_resolution ? "half resolution" : "full resolution");
}
BENCHMARK(BM_Disparity)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_DepthStage(benchmark::State& state) {
  cv::setNumThreads(1);
  semap::DepthOptions o;
  o.half_resolution = state.range(0) != 0;
  const semap::StereoDepth depth(o);
  const semap::Frame& f = AlignedFrame();
  size_t points = 0;
  for (auto _ : state) {
    const auto cloud = depth.Process(f);
    points = cloud.size();
    benchmark::DoNotOptimize(cloud.positions_world.data());
  }
  state.counters["points"] = static_cast<double>(points);
  state.SetLabel(o.half_resolution ? "half resolution" : "full resolution");
}
BENCHMARK(BM_DepthStage)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_ToCloud(benchmark::State& state) {
  const semap::StereoDepth depth{semap::DepthOptions{}};
  const auto& f = TestFrame().frame;
  cv::setNumThreads(1);
  const semap::DisparityResult r = depth.Compute(f.left, f.right);
  for (auto _ : state) benchmark::DoNotOptimize(depth.ToCloud(f, r.disparity_px, r.confidence));
}
BENCHMARK(BM_ToCloud)->Unit(benchmark::kMillisecond);

void BM_FitRowOffsets(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& f = TestFrame().frame;
  for (auto _ : state) benchmark::DoNotOptimize(semap::FitRowOffsets(f.left, f.right));
}
BENCHMARK(BM_FitRowOffsets)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
