// Visual odometry end to end: `semap run` on a generated drive whose poses were taken away (input.poses: auto
// falls back to odometry), its outputs, `semap eval-poses` against the drive's own poses, input.poses errors,
// and the hostile input of the README's Faults table (blank, duplicated, swapped and dropped frames).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

constexpr int kFrames = 12;
// Large enough for the odometry's corners (min_inliers of them), small enough for a run of seconds.
const std::string kSize =
    " --set synth.image_width_px=640 --set synth.image_height_px=192 --set synth.cx_px=320"
    " --set synth.cy_px=96 --set synth.lidar_azimuth_steps=256";
const std::string kFast = " --set depth.max_points_per_frame=1500 --set pipeline.depth_workers=1";
constexpr int kRunTimeoutS = 300;

std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') out.push_back(line);
  }
  return out;
}

std::string Name(int i) {
  char name[32];
  std::snprintf(name, sizeof(name), "%010d.png", i);
  return name;
}

class Odometry : public ::testing::Test {
 protected:
  static fs::path Pristine() { return test::ProcessTempRoot() / "Odometry_sequence"; }
  static fs::path Drive(const fs::path& seq) { return seq / "2026_01_01" / "2026_01_01_drive_0001_sync"; }

  static void SetUpTestSuite() {
    fs::remove_all(Pristine());
    const CliRun r = test::RunSemap("synth --preset urban --frames " + std::to_string(kFrames) +
                                    " --seed 5 --out " + Pristine().string() + kSize);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }

  // Each test's copy, without poses (no oxts/).
  void SetUp() override {
    dir_ = test::TempDir();
    fs::copy(Pristine(), dir_ / "seq", fs::copy_options::recursive);
    fs::remove_all(Drive(dir_ / "seq") / "oxts");
    out_ = dir_ / "out";
  }

  CliRun Run(const std::string& extra = "") const {
    return test::RunShell("timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) + " run " +
                          (dir_ / "seq").string() + " --out " + out_.string() + kFast + extra);
  }

  fs::path Image(int cam, int i) const {
    return Drive(dir_ / "seq") / ("image_0" + std::to_string(cam)) / "data" / Name(i);
  }

  // The odometry_status column of frames.csv, by frame id.
  std::map<int, int> Statuses() const {
    const std::vector<std::string> rows = Lines(out_ / "frames.csv");
    std::map<int, int> out;
    if (rows.empty()) return out;
    std::vector<std::string> header;
    std::stringstream hs(rows[0]);
    for (std::string c; std::getline(hs, c, ',');) header.push_back(c);
    const auto col = std::find(header.begin(), header.end(), "odometry_status") - header.begin();
    for (size_t r = 1; r < rows.size(); ++r) {
      std::stringstream rs(rows[r]);
      std::vector<std::string> cells;
      for (std::string c; std::getline(rs, c, ',');) cells.push_back(c);
      if (static_cast<size_t>(col) < cells.size()) out[std::stoi(cells[0])] = std::stoi(cells[col]);
    }
    return out;
  }

  fs::path dir_, out_;
};

// No poses at all: auto runs the odometry; the map, the trajectory files and the per-frame figures are
// written, and the trajectory matches the drive's own poses (which eval-poses reads from the pristine copy).
TEST_F(Odometry, SequenceWithoutPosesIsMappedFromOdometry) {
  const CliRun r = Run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("poses: stereo visual odometry")) << r.output;
  EXPECT_TRUE(r.Has("odometry: 12 frames, 0 bridged or restarted")) << r.output;
  EXPECT_EQ(Lines(out_ / "poses_odometry.txt").size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(Lines(out_ / "poses_odometry.tum").size(), static_cast<size_t>(kFrames));
  const std::vector<std::string> csv = Lines(out_ / "frames.csv");
  ASSERT_EQ(csv.size(), static_cast<size_t>(kFrames + 1));
  EXPECT_NE(
      csv[0].find("odometry_status,odometry_features,odometry_inliers,odometry_cpu_ms,odometry_ms,odometry_"
                  "disparity_offset_px,odometry_disparity_offset_per_row_px,odometry_keyframe"),
      std::string::npos);
  EXPECT_GT(fs::file_size(out_ / "mesh.ply"), 1000u);

  const fs::path json = dir_ / "eval_poses.json";
  const CliRun e = test::RunSemap("eval-poses " + Pristine().string() + " --poses " +
                                  (out_ / "poses_odometry.txt").string() + " --json " + json.string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_TRUE(e.Has("relative error over 10 frames")) << e.output;
  EXPECT_TRUE(e.Has("KITTI metric: none (the drive is shorter than 100 m)")) << e.output;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["frames"], kFrames);
  // Generated images at 640x192: a few per cent over 10 frames at most.
  EXPECT_LT(j["relative"]["drift"]["translation_percent"].get<double>(), 3.0);
  EXPECT_LT(j["absolute"]["rmse_m"].get<double>(), 0.2);
  // The TUM file says the same.
  const CliRun tum = test::RunSemap("eval-poses " + Pristine().string() + " --poses " +
                                    (out_ / "poses_odometry.tum").string());
  ASSERT_EQ(tum.exit_code, 0) << tum.output;
}

// A config error (exit 2) before any frame is read.
TEST_F(Odometry, PosesTheSequenceLacksAreAnErrorNamingTheKey) {
  for (const std::string source : {"oxts", "file"}) {
    const CliRun r = Run(" --set input.poses=" + source);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(r.Has("input.poses: " + source)) << r.output;
  }
  // The pristine copy has OXTS poses, not a pose file.
  const CliRun r = test::RunShell(std::string(SEMAP_EXE) + " run " + Pristine().string() + " --out " +
                                  out_.string() + kFast + " --set input.poses=file");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(r.Has("has no pose file")) << r.output;
}

TEST_F(Odometry, EvalPosesOfATrajectoryOfAnotherLengthNamesBothCounts) {
  std::ofstream(dir_ / "short.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const CliRun r =
      test::RunSemap("eval-poses " + Pristine().string() + " --poses " + (dir_ / "short.txt").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("has 1 poses but the sequence has 12 frames")) << r.output;
  // Nothing to evaluate against: the copy without poses.
  const CliRun none =
      test::RunSemap("eval-poses " + (dir_ / "seq").string() + " --poses " + (dir_ / "short.txt").string());
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_TRUE(none.Has("frame 0 has no pose")) << none.output;
}

// Beside the sequence's own poses: the map takes those, the odometry's trajectory and figures are written.
TEST_F(Odometry, BesideTheSequencesPoses) {
  const CliRun r = test::RunShell(std::string(SEMAP_EXE) + " run " + Pristine().string() + " --out " +
                                  out_.string() + kFast + " --set input.compare_odometry=true");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("beside the sequence's own")) << r.output;
  EXPECT_EQ(Lines(out_ / "poses_odometry.txt").size(), static_cast<size_t>(kFrames));
}

// A blank frame (both images black): tracking fails there, the frame is skipped and counted with the reason,
// and the next frame is tracked from the last good one.
TEST_F(Odometry, BlankFrameIsSkippedAndBridged) {
  for (int cam : {2, 3}) {
    const cv::Mat img = cv::imread(Image(cam, 5).string(), cv::IMREAD_UNCHANGED);
    ASSERT_TRUE(cv::imwrite(Image(cam, 5).string(), cv::Mat::zeros(img.size(), img.type())));
  }
  const CliRun r = Run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("frame 5: visual odometry lost track")) << r.output;
  EXPECT_TRUE(r.Has("odometry: 12 frames, 1 bridged or restarted")) << r.output;
  EXPECT_EQ(Lines(out_ / "poses_odometry.txt").size(), static_cast<size_t>(kFrames));
  const auto statuses = Statuses();
  EXPECT_EQ(statuses.count(5), 0u);  // not mapped
  ASSERT_EQ(statuses.count(6), 1u);
  EXPECT_EQ(statuses.at(6), 1);  // tracked
  const CliRun e = test::RunSemap("eval-poses " + Pristine().string() + " --poses " +
                                  (out_ / "poses_odometry.txt").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
}

// A duplicated frame (frame 5 repeats frame 4): no motion there, double the next; every frame is tracked.
TEST_F(Odometry, DuplicatedFrameIsTrackedAsStandingStill) {
  for (int cam : {2, 3}) fs::copy_file(Image(cam, 4), Image(cam, 5), fs::copy_options::overwrite_existing);
  const CliRun r = Run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("odometry: 12 frames, 0 bridged or restarted")) << r.output;
  const auto poses = Lines(out_ / "poses_odometry.txt");
  ASSERT_EQ(poses.size(), static_cast<size_t>(kFrames));
  auto z = [&](int i) {
    std::stringstream s(poses[static_cast<size_t>(i)]);
    double v[12];
    for (double& x : v) s >> x;
    return Eigen::Vector3d(v[3], v[7], v[11]);
  };
  EXPECT_LT((z(5) - z(4)).norm(), 0.05);
  EXPECT_GT((z(6) - z(5)).norm(), 1.0);  // two frames' drive at 8 m/s
}

// Two frames swapped on disk: the odometry follows the images (back, then forward twice), nothing is lost.
TEST_F(Odometry, SwappedFramesAreTrackedWhereTheImagesWereTaken) {
  for (int cam : {2, 3}) {
    fs::rename(Image(cam, 5), dir_ / "tmp.png");
    fs::rename(Image(cam, 6), Image(cam, 5));
    fs::rename(dir_ / "tmp.png", Image(cam, 6));
  }
  const CliRun r = Run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("odometry: 12 frames, 0 bridged or restarted")) << r.output;
  // Pose 5 is where image 6 was taken and the other way round: eval-poses sees errors only around them.
  const CliRun e = test::RunSemap("eval-poses " + Pristine().string() + " --poses " +
                                  (out_ / "poses_odometry.txt").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  const auto poses = Lines(out_ / "poses_odometry.txt");
  auto position = [&](int i) {
    std::stringstream s(poses[static_cast<size_t>(i)]);
    double v[12];
    for (double& x : v) s >> x;
    return Eigen::Vector3d(v[3], v[7], v[11]);
  };
  // Along the drive: 4 → 6 (frame 5's images) → 5 (frame 6's) → 7.
  const double d45 = (position(5) - position(4)).norm(), d46 = (position(6) - position(4)).norm();
  EXPECT_GT(d45, d46);
}

// Dropped frames (5 and 6 missing from disk): the odometry bridges the gap from the timestamps.
TEST_F(Odometry, DroppedFramesAreBridgedByTheirTimestamps) {
  for (int cam : {2, 3}) {
    fs::remove(Image(cam, 5));
    fs::remove(Image(cam, 6));
  }
  const CliRun r = Run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("odometry: 10 frames, 0 bridged or restarted")) << r.output;
  EXPECT_EQ(Statuses().size(), static_cast<size_t>(kFrames - 2));
}

}  // namespace
}  // namespace semap::tools
