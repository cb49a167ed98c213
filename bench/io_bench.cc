// Reader and writer throughput: KITTI frames from ../shared (per frame, PNG decoding included) and mesh
// files (a grid mesh of 250k vertices / 500k triangles), and a KITTI frame's depth result through the LCM
// depth-frame parts (encode: compress and cut into datagrams; decode: assemble them back). Run:
// ./build/bench/io_bench   (the depth frames only: --benchmark_filter=DepthFrame)
#include <benchmark/benchmark.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "engine/depth/stereo_depth.h"
#include "io/frame_source.h"
#include "io/kitti/calibration.h"
#include "io/lcm/depth_frames.h"
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

// The depth result of KITTI odometry 04's first colour pair, as a depth node sends it: the engine's SGBM
// disparity and confidence (full-size maps, as half-resolution matching delivers them too) and a blocky label
// image (rectangles of a dozen classes, as a segmenter's output looks).
const semap::io::DepthFrameMessage* KittiDepthFrame() {
  static const std::optional<semap::io::DepthFrameMessage> frame =
      []() -> std::optional<semap::io::DepthFrameMessage> {
    const fs::path seq = SharedData("kitti_odometry_04") / "sequences" / "04";
    if (!fs::exists(seq / "image_2" / "000000.png")) return std::nullopt;
    semap::io::DepthFrameMessage m;
    m.left = cv::imread((seq / "image_2" / "000000.png").string(), cv::IMREAD_COLOR);
    const cv::Mat right = cv::imread((seq / "image_3" / "000000.png").string(), cv::IMREAD_COLOR);
    m.calibration =
        semap::io::ReadOdometryCalibration(seq / "calib.txt", semap::io::OdometryPair::kColor).stereo;
    m.calibration.width_px = m.left.cols;
    m.calibration.height_px = m.left.rows;
    const semap::DisparityResult d = semap::StereoDepth(semap::DepthOptions{}).Compute(m.left, right);
    m.disparity_px = d.disparity_px;
    m.confidence = d.confidence;
    m.labels.create(m.left.size(), CV_8UC1);
    for (int y = 0; y < m.labels.rows; ++y) {
      for (int x = 0; x < m.labels.cols; ++x)
        m.labels.at<std::uint8_t>(y, x) =
            y > 250 ? 0 : static_cast<std::uint8_t>(1 + (x / 90 + 5 * (y / 60)) % 11);
    }
    m.frame_id = 1;
    m.world_from_cam = semap::Pose3d::Identity();
    return m;
  }();
  return frame ? &*frame : nullptr;
}

semap::io::DepthFrameOptions DepthFrameBenchOptions(const benchmark::State& state) {
  semap::io::DepthFrameOptions o;
  o.byte_shuffle = state.range(0) != 0;
  return o;
}

void ReportDepthFrame(benchmark::State& state, const std::vector<semap::io::EncodedMessage>& parts) {
  std::int64_t bytes = 0;
  for (const auto& p : parts) bytes += static_cast<std::int64_t>(p.size());
  const auto* m = KittiDepthFrame();
  state.counters["bytes_per_frame"] = static_cast<double>(bytes);
  state.counters["parts"] = static_cast<double>(parts.size());
  state.counters["MB_per_s_at_10Hz"] = 10.0 * static_cast<double>(bytes) / 1e6;
  state.counters["ratio"] =
      static_cast<double>(m->left.total() * (m->left.elemSize() + 9)) / static_cast<double>(bytes);
  state.SetLabel(std::to_string(m->left.cols) + "x" + std::to_string(m->left.rows) +
                 (state.range(0) ? " colour, byte-shuffled" : " colour"));
}

void BM_EncodeDepthFrame(benchmark::State& state) {
  const auto* m = KittiDepthFrame();
  if (!m) {
    state.SkipWithError("no kitti_odometry_04 in the shared data");
    return;
  }
  const semap::io::DepthFrameSender sender(DepthFrameBenchOptions(state), 7, 9, "bench");
  std::vector<semap::io::EncodedMessage> parts;
  for (auto _ : state) benchmark::DoNotOptimize((parts = sender.Encode(*m)).data());
  ReportDepthFrame(state, parts);
}
BENCHMARK(BM_EncodeDepthFrame)->Arg(0)->Arg(1)->ArgName("shuffle")->Unit(benchmark::kMillisecond);

void BM_DecodeDepthFrame(benchmark::State& state) {
  const auto* m = KittiDepthFrame();
  if (!m) {
    state.SkipWithError("no kitti_odometry_04 in the shared data");
    return;
  }
  const auto parts = semap::io::DepthFrameSender(DepthFrameBenchOptions(state), 7, 9, "bench").Encode(*m);
  for (auto _ : state) {
    semap::io::DepthFrameAssembler assembler(7, 9);
    std::optional<semap::io::DepthFrameMessage> frame;
    for (const auto& p : parts) frame = assembler.Add(p.data(), p.size());
    if (!frame) {
      state.SkipWithError("the frame did not assemble");
      return;
    }
    benchmark::DoNotOptimize(frame->disparity_px.data);
  }
  ReportDepthFrame(state, parts);
}
BENCHMARK(BM_DecodeDepthFrame)->Arg(0)->Arg(1)->ArgName("shuffle")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
