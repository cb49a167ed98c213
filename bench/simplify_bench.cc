// Points/s of every simplification method on a 300k-point labelled frame-like cloud, on one core
// (TBB limited to one thread), and per-frame time of the WindowedSimplifier on a stream of such frames:
// whole frames, and frames cut to a point budget the way the depth stage does (depth.max_points_per_frame,
// default 10,000: uniform decimation), which is what `semap run` gives the simplifier.
//   ./build/bench/simplify_bench [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <random>

#include "engine/depth/stereo_depth.h"
#include "engine/simplify/simplify.h"
#include "engine/simplify/windowed_simplifier.h"

namespace semap {
namespace {

constexpr Label kRoad = 1, kSidewalk = 2, kBuilding = 3, kCar = 14;

// A stereo-like frame of a street seen from a camera at x = camera_x, 1.65 m high, looking along +x
// (world: x forward, y left, z up): rays through a 1100 x 306 pixel grid (fx = 700 px) hit the road
// (|y| < 5 m), sidewalks (5-8 m), building walls (|y| = 8 m, up to 12 m high) and car boxes, up to 40 m;
// depth noise grows with range² like SGBM's (σ = 0.002 m at 1 m). About 300k points.
LabelledCloud StreetFrame(double camera_x, std::uint64_t seed) {
  constexpr int kWidth = 1100, kHeight = 306;
  constexpr double kFocalPx = 700.0, kHeightM = 1.65, kMaxRangeM = 40.0, kNoiseAt1M = 0.002;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Vector3d cam(camera_x, 0.0, kHeightM);
  struct Box {
    Eigen::Vector3d lo, hi;
  };
  std::vector<Box> cars;
  for (double x = 6.0; x < 200.0; x += 9.0) {  // parked cars on both sides, fixed in the world
    cars.push_back({{x, 3.0, 0.0}, {x + 4.2, 4.8, 1.5}});
    cars.push_back({{x + 4.0, -4.8, 0.0}, {x + 8.2, -3.0, 1.5}});
  }
  LabelledCloud c;
  c.camera_centers_world = {cam};
  c.camera_frame_ids = {static_cast<std::int64_t>(seed)};
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      // Pixel ray: image centre row at v = 100 (the camera looks slightly down at the street).
      const Eigen::Vector3d dir = Eigen::Vector3d(kFocalPx, (kWidth / 2.0 - u), (100.0 - v)).normalized();
      double best = kMaxRangeM;
      Label label = 0;
      if (dir.z() < 0.0) {
        const double t = -kHeightM / dir.z();
        if (t < best) {
          best = t;
          const double y = std::abs(cam.y() + t * dir.y());
          label = y < 5.0 ? kRoad : kSidewalk;
        }
      }
      for (double wall_y : {8.0, -8.0}) {
        if (dir.y() * wall_y <= 0.0) continue;
        const double t = (wall_y - cam.y()) / dir.y();
        if (t < best && cam.z() + t * dir.z() < 12.0) {
          best = t;
          label = kBuilding;
        }
      }
      for (const auto& b : cars) {  // slab test
        double t0 = 0.0, t1 = best;
        for (int k = 0; k < 3 && t0 <= t1; ++k) {
          const double inv = 1.0 / dir[k];
          double a = (b.lo[k] - cam[k]) * inv, bb = (b.hi[k] - cam[k]) * inv;
          if (a > bb) std::swap(a, bb);
          t0 = std::max(t0, a);
          t1 = std::min(t1, bb);
        }
        if (t0 <= t1 && t0 < best) {
          best = t0;
          label = kCar;
        }
      }
      if (label == 0) continue;
      const double range = best + kNoiseAt1M * best * best * noise(rng);
      c.positions_world.push_back(cam + range * dir);
      c.labels.push_back(label);
      c.camera_index.push_back(0);
    }
  }
  return c;
}

// The frame cut to `budget` points as the depth stage does (keep point floor(j·n/k), j < k); 0 = all.
LabelledCloud BudgetFrame(double camera_x, std::uint64_t seed, std::size_t budget) {
  LabelledCloud c = StreetFrame(camera_x, seed);
  if (budget == 0 || c.size() <= budget) return c;
  std::vector<std::uint32_t> keep;
  keep.reserve(budget);
  for (std::size_t j = 0; j < budget; ++j) keep.push_back(static_cast<std::uint32_t>(j * c.size() / budget));
  return c.Subset(keep);
}

const LabelledCloud& Frame() {
  static const LabelledCloud frame = StreetFrame(0.0, 1);
  return frame;
}

void BM_Simplify(benchmark::State& state, SimplifyMethod method) {
  tbb::global_control one_core(tbb::global_control::max_allowed_parallelism, 1);
  const LabelledCloud& cloud = Frame();
  SimplifyOptions o;
  o.method = method;
  std::uint64_t kept = 0;
  for (auto _ : state) {
    const SimplifyResult r = Simplify(cloud, ClassMap::Cityscapes(), o);
    kept = r.kept();
    benchmark::DoNotOptimize(kept);
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["kept%"] = 100.0 * static_cast<double>(kept) / static_cast<double>(cloud.size());
  state.counters["points/s"] =
      benchmark::Counter(static_cast<double>(cloud.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// One WindowedSimplifier (window of range(0) frames) over a drive at 1 m per frame, one core: the time per
// frame after a warm-up of one window, and the kept share of the target classes. range(1): the point budget
// per frame (0 = the whole 300k-point frame).
void BM_Windowed(benchmark::State& state, SimplifyMethod method) {
  tbb::global_control one_core(tbb::global_control::max_allowed_parallelism, 1);
  SimplifyOptions o;
  o.method = method;
  o.window_frames = static_cast<int>(state.range(0));
  WindowedSimplifier ws(o, ClassMap::Cityscapes());
  const auto budget = static_cast<std::size_t>(state.range(1));
  int n = 0;
  for (; n < o.window_frames; ++n) ws.Process(BudgetFrame(n, n + 1, budget));
  std::uint64_t in = 0, kept = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const LabelledCloud frame = BudgetFrame(n, n + 1, budget);
    ++n;
    state.ResumeTiming();
    const auto out = ws.Process(frame);
    for (const auto& s : out.result.per_class) {
      if (ClassMap::Cityscapes().IsTarget(s.label)) {
        in += s.in;
        kept += s.kept;
      }
    }
  }
  state.counters["frames/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["target_kept%"] = in > 0 ? 100.0 * static_cast<double>(kept) / static_cast<double>(in) : 0.0;
}

}  // namespace
}  // namespace semap

int main(int argc, char** argv) {
  using namespace semap;
  // depth.max_points_per_frame's default: what the simplifier gets per frame in `semap run`.
  const int default_point_budget = DepthOptions{}.max_points_per_frame;
  for (auto m : AllSimplifyMethods()) {
    benchmark::RegisterBenchmark((std::string("Simplify/") + SimplifyMethodName(m)).c_str(), BM_Simplify, m)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2);
  }
  for (auto m : {SimplifyMethod::kLinearRadius, SimplifyMethod::kProbabilistic}) {
    benchmark::RegisterBenchmark((std::string("Windowed/") + SimplifyMethodName(m)).c_str(), BM_Windowed, m)
        ->Args({5, 0})
        ->Args({30, 0})
        ->Args({5, default_point_budget})
        ->Unit(benchmark::kMillisecond)
        ->Iterations(10);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
