// Plane-sweep depth cost on real views: fountain-P11 (1536×1024, a view and its 4 nearest neighbours, as
// `semap run` sweeps it) and KITTI odometry 04 (1242×375, frame 25's left image against the left images of
// frames 23, 24, 26 and 27 with their poses), at full and half resolution and at 32, 64 and 128 planes, on
// every core TBB is given (the sweep runs its bands in parallel; cv::setNumThreads(1)). Counters: ms per
// plane (the fronto-parallel family), the share of pixels given a depth.
// Run: taskset -c 0,1 ./build/bench/plane_sweep_bench  (SEMAP_SHARED overrides the shared folder)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "engine/depth/frame_sweep.h"
#include "io/frame_source.h"

namespace {

std::string Shared() {
  const char* env = std::getenv("SEMAP_SHARED");
  return env ? env : std::string(SEMAP_SHARED_DIR);
}

// Frame `id` of a Strecha set as `semap run` reads it (with its neighbour views).
semap::Frame FountainFrame(int id) {
  semap::io::FrameSourceOptions o;
  o.first_frame = id;
  o.max_frames = 1;
  o.load_labels = false;
  return *semap::io::OpenFrameSource(Shared() + "/data/strecha_fountain_p11", o)->Next();
}

// KITTI odometry 04 frame `id`'s left image with the left images of the frames `offsets` away as its
// neighbour views; its baseline the distance to the nearest of them.
semap::Frame KittiFrame(int id, const std::vector<int>& offsets) {
  semap::io::FrameSourceOptions o;
  o.load_velodyne = false;
  o.load_labels = false;
  auto source = semap::io::OpenFrameSource(Shared() + "/data/kitti_odometry_04", o);
  std::vector<semap::Frame> frames;
  while (auto f = source->Next()) frames.push_back(std::move(*f));
  semap::Frame reference = frames.at(static_cast<size_t>(id));
  reference.right = cv::Mat();
  double nearest_m = 1e9;
  for (const int offset : offsets) {
    const semap::Frame& n = frames.at(static_cast<size_t>(id + offset));
    semap::CalibratedView view = semap::ReferenceView(n, 1.0);
    nearest_m = std::min(nearest_m,
                         (n.world_from_cam->translation() - reference.world_from_cam->translation()).norm());
    reference.neighbour_views.push_back(std::move(view));
  }
  reference.calibration.baseline_m = nearest_m;
  return reference;
}

// `range`: the depths swept (both 0: from the cameras, where their optical axes meet).
void Sweep(benchmark::State& state, const semap::Frame& frame, semap::DepthRange range = {}) {
  cv::setNumThreads(1);
  semap::PlaneSweepOptions o;
  o.num_planes = static_cast<int>(state.range(1));
  o.min_depth_m = range.min_depth_m;
  o.max_depth_m = range.max_depth_m;
  const semap::PlaneSweepDepth sweep(o);
  const bool half = state.range(0) != 0;
  double valid = 0.0;
  for (auto _ : state) {
    const semap::DisparityResult r = semap::SweepFrameDisparity(frame, sweep, half);
    valid = static_cast<double>(cv::countNonZero(r.confidence)) / static_cast<double>(r.confidence.total());
  }
  state.counters["ms_per_plane"] = benchmark::Counter(
      o.num_planes / 1e3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["valid_share"] = valid;
  state.SetLabel(std::to_string(frame.left.cols) + "x" + std::to_string(frame.left.rows) + ", " +
                 std::to_string(frame.neighbour_views.size()) + " neighbours, " +
                 (half ? "half resolution" : "full resolution"));
}

void BM_SweepFountain(benchmark::State& state) {
  static const semap::Frame frame = FountainFrame(5);
  Sweep(state, frame);
}
BENCHMARK(BM_SweepFountain)
    ->ArgsProduct({{1, 0}, {32, 64, 128}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

void BM_SweepKitti(benchmark::State& state) {
  static const semap::Frame frame = KittiFrame(25, {-2, -1, 1, 2});
  // A forward-driving camera's optical axes are nearly parallel: the range is depth.min/max_depth_m's.
  Sweep(state, frame, {1.0, 40.0});
}
BENCHMARK(BM_SweepKitti)
    ->ArgsProduct({{1, 0}, {32, 64, 128}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
