// Reader and writer throughput: KITTI frames from ../shared (per frame, PNG decoding included) and mesh
// files (a grid mesh of 250k vertices / 500k triangles). Run: ./build/bench/io_bench
#include <benchmark/benchmark.h>

#include <filesystem>

#include "io/frame_source.h"
#include "io/mesh/ply_off.h"

namespace {

namespace fs = std::filesystem;

fs::path SharedData(const char* name) {
  const char* env = std::getenv("SEMAP_SHARED");
  return fs::path(env && *env ? env : SEMAP_SHARED_DIR) / "data" / name;
}

void ReadFrames(benchmark::State& state, const fs::path& path, bool velodyne) {
  if (!fs::exists(path)) {
    state.SkipWithError(("no data at " + path.string()).c_str());
    return;
  }
  semap::io::FrameSourceOptions o;
  o.load_velodyne = velodyne;
  auto source = semap::io::OpenFrameSource(path, o);
  std::int64_t frames = 0;
  for (auto _ : state) {
    auto f = source->Next();
    if (!f) {
      state.PauseTiming();
      source = semap::io::OpenFrameSource(path, o);
      state.ResumeTiming();
      f = source->Next();
    }
    benchmark::DoNotOptimize(f->left.data);
    ++frames;
  }
  state.SetItemsProcessed(frames);
}

void BM_ReadStereo2015Frame(benchmark::State& state) {
  ReadFrames(state, SharedData("kitti_stereo2015_subset"), state.range(0) != 0);
}
BENCHMARK(BM_ReadStereo2015Frame)->Arg(0)->Arg(1)->ArgName("velodyne")->Unit(benchmark::kMillisecond);

void BM_ReadOdometryFrame(benchmark::State& state) {
  ReadFrames(state, SharedData("kitti_odometry_03"), false);
}
BENCHMARK(BM_ReadOdometryFrame)->Unit(benchmark::kMillisecond);

semap::Mesh GridMesh(int n) {
  semap::Mesh m;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      m.vertices.emplace_back(x * 0.05 + 100.0, y * 0.05 - 20.0, 0.01 * ((x * 7 + y * 3) % 11));
      m.colors_rgb.push_back({static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), 128});
      m.labels.push_back(static_cast<semap::Label>((x + y) % 20));
    }
  }
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      const std::uint32_t i = y * n + x;
      m.triangles.push_back({i, i + 1, i + n});
      m.triangles.push_back({i + 1, i + n + 1, i + n});
    }
  }
  return m;
}

const semap::Mesh& BenchMesh() {
  static const semap::Mesh mesh = GridMesh(500);
  return mesh;
}

fs::path BenchFile(const char* name) {
  return fs::temp_directory_path() / (std::string("semap_io_bench_") + name);
}

void BM_WriteMeshPly(benchmark::State& state) {
  const auto encoding =
      state.range(0) ? semap::io::PlyEncoding::kAscii : semap::io::PlyEncoding::kBinaryLittleEndian;
  const fs::path path = BenchFile("w.ply");
  for (auto _ : state) semap::io::WriteMeshPly(path, BenchMesh(), encoding);
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(fs::file_size(path)));
  fs::remove(path);
}
BENCHMARK(BM_WriteMeshPly)->Arg(0)->Arg(1)->ArgName("ascii")->Unit(benchmark::kMillisecond);

void BM_ReadMeshPly(benchmark::State& state) {
  const auto encoding =
      state.range(0) ? semap::io::PlyEncoding::kAscii : semap::io::PlyEncoding::kBinaryLittleEndian;
  const fs::path path = BenchFile("r.ply");
  semap::io::WriteMeshPly(path, BenchMesh(), encoding);
  for (auto _ : state) benchmark::DoNotOptimize(semap::io::ReadMeshPly(path).vertices.data());
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(fs::file_size(path)));
  fs::remove(path);
}
BENCHMARK(BM_ReadMeshPly)->Arg(0)->Arg(1)->ArgName("ascii")->Unit(benchmark::kMillisecond);

void BM_OffSizeBytes(benchmark::State& state) {
  std::uint64_t bytes = 0;
  for (auto _ : state) benchmark::DoNotOptimize(bytes = semap::io::OffSizeBytes(BenchMesh()));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes));
}
BENCHMARK(BM_OffSizeBytes)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
