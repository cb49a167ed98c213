#include "io/synth/kitti_raw_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "io/frame_source.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

sim::SynthOptions Opts(std::uint64_t seed) {
  sim::SynthOptions o;
  o.preset = sim::ScenePreset::kMixed;
  o.num_frames = 3;
  o.seed = seed;
  return o;
}

std::string ReadAll(const fs::path& p) {
  std::ifstream is(p, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

// "KEY: v1 v2 ..." lines of a KITTI calib file.
std::map<std::string, std::vector<double>> ParseCalib(const fs::path& p) {
  std::map<std::string, std::vector<double>> out;
  std::ifstream is(p);
  std::string line;
  while (std::getline(is, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream vs(line.substr(colon + 1));
    std::vector<double> v;
    double x;
    while (vs >> x) v.push_back(x);
    out[line.substr(0, colon)] = v;
  }
  return out;
}

std::map<std::string, std::string> AllFiles(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), root).string()] = ReadAll(e.path());
  }
  return files;
}

TEST(KittiRawWriter, WritesTheKittiRawLayoutWithExactGroundTruth) {
  const sim::SyntheticSequence seq(Opts(1));
  const fs::path root = test::TempDir() / "seq";
  int calls = 0;
  const SynthWriteSummary summary = WriteSyntheticKittiRaw(seq, root, [&](int done, int total) {
    ++calls;
    EXPECT_LE(done, total);
  });
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(summary.num_frames, 3);
  EXPECT_EQ(summary.label_pixels.total(), 3u * 1242 * 375);
  const fs::path drive = root / "2026_01_01" / "2026_01_01_drive_0001_sync";
  EXPECT_EQ(summary.layout.drive_dir, drive);
  for (const char* d : {"image_02", "image_03", "velodyne_points", "oxts", "semantic", "depth"}) {
    const std::string stamps = ReadAll(drive / d / "timestamps.txt");
    EXPECT_EQ(stamps,
              "2026-01-01 12:00:00.000000000\n2026-01-01 12:00:00.100000000\n2026-01-01 12:00:00.200000000\n")
        << d;
  }
  ASSERT_TRUE(fs::exists(drive / "scene_mesh.ply"));
  ASSERT_TRUE(fs::exists(drive / "oxts" / "dataformat.txt"));

  // Calibration: KITTI keys, and the conventions a reader uses give back the rig.
  const auto cam = ParseCalib(root / "2026_01_01" / "calib_cam_to_cam.txt");
  for (const char* k : {"S", "K", "D", "R", "T", "S_rect", "R_rect", "P_rect"}) {
    for (const char* n : {"00", "01", "02", "03"}) EXPECT_TRUE(cam.count(std::string(k) + "_" + n)) << k << n;
  }
  EXPECT_TRUE(cam.count("calib_time"));
  const auto& p2 = cam.at("P_rect_02");
  const auto& p3 = cam.at("P_rect_03");
  ASSERT_EQ(p2.size(), 12u);
  EXPECT_DOUBLE_EQ(p2[0], 721.5377);
  EXPECT_DOUBLE_EQ(p2[2], 609.5593);
  EXPECT_DOUBLE_EQ(p2[6], 172.854);
  EXPECT_NEAR((p2[3] - p3[3]) / p2[0], 0.54, 1e-12);
  EXPECT_EQ(cam.at("S_rect_02"), (std::vector<double>{1242, 375}));
  const auto velo = ParseCalib(root / "2026_01_01" / "calib_velo_to_cam.txt");
  const auto imu = ParseCalib(root / "2026_01_01" / "calib_imu_to_velo.txt");
  ASSERT_EQ(velo.at("R").size(), 9u);
  ASSERT_EQ(velo.at("T").size(), 3u);
  ASSERT_EQ(imu.at("R").size(), 9u);
  Pose3d velo_to_cam = Pose3d::Identity(), imu_to_velo = Pose3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      velo_to_cam.linear()(r, c) = velo.at("R")[3 * r + c];
      imu_to_velo.linear()(r, c) = imu.at("R")[3 * r + c];
    }
    velo_to_cam.translation()[r] = velo.at("T")[r];
    imu_to_velo.translation()[r] = imu.at("T")[r];
  }
  // cam2_from_velo = T(x = P_rect_02[0,3] / fx) * R_rect_00 (identity here) * [R|T]_velo_to_cam.
  const Pose3d cam2_from_velo = Pose3d(Eigen::Translation3d(p2[3] / p2[0], 0, 0)) * velo_to_cam;
  EXPECT_TRUE(cam2_from_velo.isApprox(seq.rig().cam2_from_velo(), 1e-12));
  EXPECT_TRUE((cam2_from_velo * imu_to_velo).isApprox(seq.rig().cam2_from_imu(), 1e-12));

  // Per-frame files equal the rendered frame (PNG is lossless; depth in mm; scan as float32 quadruples).
  const sim::SyntheticFrame f = seq.RenderFrame(2);
  const fs::path name = "0000000002";
  const cv::Mat left =
      cv::imread((drive / "image_02" / "data" / name).string() + ".png", cv::IMREAD_UNCHANGED);
  const cv::Mat right =
      cv::imread((drive / "image_03" / "data" / name).string() + ".png", cv::IMREAD_UNCHANGED);
  const cv::Mat labels =
      cv::imread((drive / "semantic" / "data" / name).string() + ".png", cv::IMREAD_UNCHANGED);
  const cv::Mat depth = cv::imread((drive / "depth" / "data" / name).string() + ".png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(left.type(), CV_8UC3);
  ASSERT_EQ(labels.type(), CV_8UC1);
  ASSERT_EQ(depth.type(), CV_16UC1);
  EXPECT_EQ(left.cols, 1242);
  EXPECT_EQ(left.rows, 375);
  EXPECT_EQ(cv::norm(left, f.left.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(right, f.right.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(labels, f.left.labels, cv::NORM_INF), 0.0);
  int with_depth = 0;
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      const float z = f.left.depth_m.at<float>(y, x);
      const std::uint16_t mm = depth.at<std::uint16_t>(y, x);
      if (z > 0.0f && std::round(z * 1000.0) <= 65535.0) {
        ++with_depth;
        ASSERT_NEAR(mm / 1000.0, z, 0.0005 + 1e-6) << x << "," << y;
      } else {
        ASSERT_EQ(mm, 0) << x << "," << y;
      }
    }
  }
  EXPECT_GT(with_depth, 1242 * 375 / 2);
  const std::string scan = ReadAll(drive / "velodyne_points" / "data" / (name.string() + ".bin"));
  ASSERT_EQ(scan.size(), 16u * f.scan.points_velo.size());
  EXPECT_EQ(0, std::memcmp(scan.data(), f.scan.points_velo.data(), scan.size()));

  // The scene mesh in the world frame (IMU of frame 0) with per-vertex labels.
  const Mesh mesh = ReadMeshPly(drive / "scene_mesh.ply");
  ASSERT_EQ(mesh.num_triangles(), seq.scene().num_triangles());
  ASSERT_EQ(mesh.labels.size(), mesh.num_vertices());
  const Eigen::Vector3d v = seq.world_from_scene() * seq.scene().vertices[10];
  EXPECT_LT((mesh.vertices[10] - v).norm(), 1e-9);
}

TEST(KittiRawWriter, SameSeedGivesByteIdenticalOutput) {
  auto opts = [](std::uint64_t seed) {
    sim::SynthOptions o = Opts(seed);
    o.num_frames = 2;
    return o;
  };
  const fs::path a = test::TempDir() / "a", b = test::TempDir() / "b", c = test::TempDir() / "c";
  WriteSyntheticKittiRaw(sim::SyntheticSequence(opts(9)), a);
  WriteSyntheticKittiRaw(sim::SyntheticSequence(opts(9)), b);
  WriteSyntheticKittiRaw(sim::SyntheticSequence(opts(10)), c);
  const auto fa = AllFiles(a), fb = AllFiles(b), fc = AllFiles(c);
  ASSERT_GT(fa.size(), 15u);
  ASSERT_EQ(fa.size(), fb.size());
  for (const auto& [path, bytes] : fa) {
    ASSERT_TRUE(fb.count(path)) << path;
    EXPECT_TRUE(bytes == fb.at(path)) << path << " differs between two runs with the same seed";
  }
  const std::string left = "2026_01_01/2026_01_01_drive_0001_sync/image_02/data/0000000001.png";
  EXPECT_FALSE(fa.at(left) == fc.at(left));  // another seed, another sequence
}

// The round trip through the project's KITTI raw reader: poses (from OXTS + calib), calibration, Velodyne,
// labels and timestamps come back as generated.
TEST(KittiRawWriter, TheKittiRawReaderRecoversTheGroundTruth) {
  sim::SynthOptions o = Opts(6);
  o.num_frames = 4;
  o.speed_mps = 12.0;
  const sim::SyntheticSequence seq(o);
  const fs::path root = test::TempDir() / "rt";
  const SynthWriteSummary summary = WriteSyntheticKittiRaw(seq, root);
  auto source = OpenFrameSource(summary.layout.drive_dir, FrameSourceOptions{});
  ASSERT_EQ(source->layout(), DatasetLayout::kKittiRaw);
  ASSERT_EQ(source->size(), 4);
  int n = 0;
  while (auto f = source->Next()) {
    const int i = static_cast<int>(f->id);
    ASSERT_TRUE(f->world_from_cam.has_value());
    const Pose3d truth = seq.world_from_cam2(i);
    EXPECT_LT((f->world_from_cam->translation() - truth.translation()).norm(), 1e-6) << "frame " << i;
    EXPECT_LT((f->world_from_cam->linear() - truth.linear()).norm(), 1e-9) << "frame " << i;
    // The reader goes through absolute (epoch) seconds in a double: ~2e-7 s resolution.
    EXPECT_NEAR(f->timestamp_s, 0.1 * i, 1e-6);
    EXPECT_NEAR(f->calibration.baseline_m, 0.54, 1e-12);
    EXPECT_NEAR(f->calibration.fx_px, 721.5377, 1e-12);
    ASSERT_TRUE(f->velodyne.has_value());
    EXPECT_TRUE(f->velodyne->cam_from_velo.isApprox(seq.rig().cam2_from_velo(), 1e-12));
    const sim::SyntheticFrame g = seq.RenderFrame(i);
    ASSERT_EQ(f->velodyne->points_velo.size(), g.scan.points_velo.size());
    EXPECT_EQ(f->velodyne->points_velo[100], g.scan.points_velo[100]);
    ASSERT_FALSE(f->labels.empty());
    EXPECT_EQ(cv::norm(f->labels, g.left.labels, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(f->left, g.left.color, cv::NORM_INF), 0.0);
    ++n;
  }
  EXPECT_EQ(n, 4);
  // The drive moved: the last camera is 3 frames x 1.2 m from the first.
  EXPECT_NEAR((seq.world_from_cam2(3).translation() - seq.world_from_cam2(0).translation()).norm(), 3.6,
              0.01);
}

TEST(KittiRawWriter, TimestampsAndUnwritableRoot) {
  EXPECT_EQ(FormatKittiTimestamp(0.0), "2026-01-01 12:00:00.000000000");
  EXPECT_EQ(FormatKittiTimestamp(3723.25), "2026-01-01 13:02:03.250000000");
  const fs::path file = test::TempDir() / "not_a_folder";
  std::ofstream(file) << "x";
  sim::SynthOptions o = Opts(1);
  o.num_frames = 1;
  EXPECT_THROW(WriteSyntheticKittiRaw(sim::SyntheticSequence(o), file / "sub"), FileError);
}

}  // namespace
}  // namespace semap::io
