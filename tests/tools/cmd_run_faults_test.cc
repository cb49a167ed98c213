// Faults while streaming, end to end through `semap run` on a small generated sequence that each test damages
// in its own copy: what the README's "Faults" table documents, checked one fault at a time. No run may crash
// or hang (every run is bounded by `timeout`; a hang is exit code 124).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

constexpr int kFrames = 8;
// Small images and few map points keep each run to seconds; one depth worker keeps the load of a parallel
// ctest low.
const std::string kSmall =
    " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160"
    " --set synth.cy_px=48 --set synth.lidar_azimuth_steps=256";
const std::string kFast = " --set depth.max_points_per_frame=1500 --set pipeline.depth_workers=1";
constexpr int kRunTimeoutS = 300;

std::string Frame(int i, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof(name), "%010d.%s", i, ext);
  return name;
}

std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// The generated sequence (once per test binary) and each test's own copy of it.
class RunFaults : public ::testing::Test {
 protected:
  static fs::path Pristine() { return fs::temp_directory_path() / "semap_test_RunFaults_sequence"; }

  static void SetUpTestSuite() {
    fs::remove_all(Pristine());
    const CliRun r = test::RunSemap("synth --preset urban --frames " + std::to_string(kFrames) +
                                    " --seed 5 --out " + Pristine().string() + kSmall);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }

  void SetUp() override {
    dir_ = test::TempDir();
    fs::copy(Pristine(), dir_ / "seq", fs::copy_options::recursive);
    drive_ = dir_ / "seq" / "2026_01_01" / "2026_01_01_drive_0001_sync";
    out_ = dir_ / "out";
  }

  // `semap run` on the damaged copy, bounded in time.
  CliRun Run(const std::string& extra = "") const {
    return test::RunShell("timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) + " run " +
                          (dir_ / "seq").string() + " --out " + out_.string() + kFast + extra);
  }

  // `semap run` started in the background (its output in run.log); the test signals or waits for it.
  pid_t Start(const std::string& extra) const {
    const std::string cmd = "exec " + std::string(SEMAP_EXE) + " run " + (dir_ / "seq").string() + " --out " +
                            out_.string() + kFast + extra + " >" + (dir_ / "run.log").string() + " 2>&1";
    const pid_t pid = fork();
    if (pid == 0) {
      execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    return pid;
  }

  // Waits for the child at most `timeout_s`; kills it and returns -1 when it hangs, else its exit code
  // (-1000 - signal when a signal ended it).
  static int Wait(pid_t pid, int timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1000 - WTERMSIG(status);
  }

  // Blocks until frames.csv holds `rows` frames (its header aside) or the child ended; false on timeout.
  bool WaitForRows(pid_t pid, const fs::path& csv, int rows, int timeout_s) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (static_cast<int>(Lines(csv).size()) >= rows + 1) return true;
      if (kill(pid, 0) != 0) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  std::string Log() const {
    std::ifstream in(dir_ / "run.log");
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }

  // The run finished with `failed` frames skipped (the others processed), and wrote a mesh.
  void ExpectSkipped(const CliRun& r, const std::vector<std::int64_t>& failed) const {
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const auto summary = ReadJson(out_ / "summary.json");
    EXPECT_EQ(summary["frames_processed"], kFrames - static_cast<int>(failed.size())) << summary.dump();
    EXPECT_EQ(summary["frames_failed"], static_cast<int>(failed.size())) << summary.dump();
    EXPECT_EQ(Lines(out_ / "frames.csv").size(), static_cast<size_t>(kFrames - failed.size() + 1));
    const auto errors = Lines(out_ / "errors.jsonl");
    ASSERT_EQ(errors.size(), failed.size());
    for (size_t i = 0; i < failed.size(); ++i) EXPECT_EQ(nlohmann::json::parse(errors[i])["frame_id"], failed[i]);
    EXPECT_GT(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), 0u);
  }

  // The error recorded for the first skipped frame.
  nlohmann::json FirstError() const { return nlohmann::json::parse(Lines(out_ / "errors.jsonl").at(0)); }

  fs::path dir_, drive_, out_;
};

TEST_F(RunFaults, IntactSequenceRunsClean) {
  const CliRun r = Run();
  ExpectSkipped(r, {});
}

TEST_F(RunFaults, CorruptImageMidSequenceIsSkippedAndCounted) {
  const fs::path left = drive_ / "image_02/data" / Frame(3, "png");
  std::string bytes = test::ReadTextFile(left);
  for (size_t i = 60; i < bytes.size(); ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  test::WriteTextFile(left, bytes);
  const CliRun r = Run();
  ExpectSkipped(r, {3});
  const auto e = FirstError();
  EXPECT_EQ(e["stage"], "read");
  EXPECT_NE(e["error"].get<std::string>().find(left.string()), std::string::npos) << e.dump();
  EXPECT_TRUE(r.Has("frame 3 skipped")) << r.output;
}

TEST_F(RunFaults, MissingVelodyneScanDoesNotCostTheFrame) {
  // The run does not use the scans (they serve evaluation): every frame is processed.
  const fs::path scan = drive_ / "velodyne_points/data" / Frame(2, "bin");
  fs::remove(scan);
  ExpectSkipped(Run(), {});
  // Evaluation skips that frame, counts it and names the file.
  const CliRun eval = test::RunShell("timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) +
                                     " eval " + (dir_ / "seq").string() + " --mesh " + (out_ / "mesh.ply").string());
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(eval.Has(std::to_string(kFrames - 1) + " evaluated (" + std::to_string(kFrames - 1) + " with Velodyne"))
      << eval.output;
  EXPECT_TRUE(eval.Has("1 frame(s) could not be read")) << eval.output;
  EXPECT_TRUE(eval.Has(scan.string())) << eval.output;
}

TEST_F(RunFaults, MissingLabelImageIsSkippedAndCounted) {
  const fs::path label = drive_ / "semantic/data" / Frame(4, "png");
  fs::remove(label);
  ExpectSkipped(Run(), {4});
  const auto e = FirstError();
  EXPECT_EQ(e["stage"], "read");
  EXPECT_NE(e["error"].get<std::string>().find(label.string()), std::string::npos) << e.dump();
  EXPECT_NE(e["error"].get<std::string>().find("label image not found"), std::string::npos) << e.dump();
}

// Rewrites value `index` (0-based) of frame `frame`'s OXTS line.
void EditOxts(const fs::path& drive, int frame, int index, const std::string& value) {
  const fs::path path = drive / "oxts/data" / Frame(frame, "txt");
  std::istringstream in(test::ReadTextFile(path));
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  ASSERT_EQ(tokens.size(), 30u);
  tokens[index] = value;
  std::string line;
  for (const auto& t : tokens) line += (line.empty() ? "" : " ") + t;
  test::WriteTextFile(path, line + "\n");
}

TEST_F(RunFaults, NanPoseIsSkippedNamingTheFile) {
  EditOxts(drive_, 5, 3, "nan");  // roll
  ExpectSkipped(Run(), {5});
  const auto e = FirstError();
  EXPECT_NE(e["error"].get<std::string>().find((drive_ / "oxts/data" / Frame(5, "txt")).string()), std::string::npos)
      << e.dump();
  EXPECT_NE(e["error"].get<std::string>().find("not finite"), std::string::npos) << e.dump();
}

TEST_F(RunFaults, JumpingPoseIsSkippedAndTheDriveGoesOn) {
  // A GPS glitch: frame 4 is 0.01° of latitude (about 1.1 km) off; frame 5 is back on the track.
  const fs::path oxts = drive_ / "oxts/data" / Frame(4, "txt");
  std::istringstream in(test::ReadTextFile(oxts));
  double lat = 0.0;
  in >> lat;
  char value[64];
  std::snprintf(value, sizeof(value), "%.12f", lat + 0.01);
  EditOxts(drive_, 4, 0, value);
  ExpectSkipped(Run(), {4});
  const auto e = FirstError();
  EXPECT_EQ(e["stage"], "pose");
  EXPECT_NE(e["error"].get<std::string>().find("pose jumps"), std::string::npos) << e.dump();
  EXPECT_NE(e["error"].get<std::string>().find("since frame 3"), std::string::npos) << e.dump();
}

TEST_F(RunFaults, FrameWithoutValidDisparityIsSkippedAndCounted) {
  // Both cameras see a uniform grey: SGBM finds no match.
  for (const char* cam : {"image_02", "image_03"}) {
    const fs::path path = drive_ / cam / "data" / Frame(2, "png");
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty());
    ASSERT_TRUE(cv::imwrite(path.string(), cv::Mat(image.size(), image.type(), cv::Scalar(90, 90, 90))));
  }
  ExpectSkipped(Run(), {2});
  const auto e = FirstError();
  EXPECT_EQ(e["stage"], "depth");
  EXPECT_NE(e["error"].get<std::string>().find("no valid disparity"), std::string::npos) << e.dump();
}

TEST_F(RunFaults, InvalidLcmUrlIsAClearErrorBeforeAnyWork) {
  const CliRun r = Run(" --lcm-url 'bogus://nowhere:1'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("bogus://nowhere:1")) << r.output;
  EXPECT_FALSE(r.Has("frames processed")) << r.output;
  EXPECT_FALSE(fs::exists(out_ / "mesh.ply"));
}

TEST_F(RunFaults, AbsentLcmSubscriberDoesNotStopTheRun) {
  // Nobody listens on this group/port (ttl=0: nothing leaves the host).
  const CliRun r = Run(" --lcm-url 'udpm://239.255.76.68:7689?ttl=0'");
  ExpectSkipped(r, {});
  EXPECT_TRUE(r.Has("LCM: ")) << r.output;
  EXPECT_FALSE(r.Has("LCM: 0 mesh messages, 0 other")) << r.output;  // published (or counted as failed)
}

TEST_F(RunFaults, OutputFolderBecomingUnwritableIsReportedNamingThePath) {
  // Mid-run the output folder is replaced by a file (as root, permissions would not stop the writes).
  const pid_t pid = Start(" --set input.loops=3");
  ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", 2, kRunTimeoutS)) << Log();
  fs::rename(out_, dir_ / "moved");
  test::WriteTextFile(out_, "not a folder");
  const int code = Wait(pid, kRunTimeoutS);
  const std::string log = Log();
  ASSERT_NE(code, -1) << "hang\n" << log;
  EXPECT_EQ(code, 1) << log;
  EXPECT_NE(log.find(std::to_string(3 * kFrames) + " frames processed"), std::string::npos) << log;
  EXPECT_NE(log.find("output errors"), std::string::npos) << log;
  EXPECT_NE(log.find(out_.string() + "/mesh.ply"), std::string::npos) << log;
  // The files opened before the folder moved kept every frame.
  EXPECT_EQ(Lines(dir_ / "moved" / "frames.csv").size(), static_cast<size_t>(3 * kFrames + 1));
}

TEST_F(RunFaults, SigintStopsCleanlyWithTheMeshSoFar) {
  const pid_t pid = Start(" --set input.loops=100");
  ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", 3, kRunTimeoutS)) << Log();
  ASSERT_EQ(kill(pid, SIGINT), 0);
  const int code = Wait(pid, kRunTimeoutS);
  const std::string log = Log();
  ASSERT_NE(code, -1) << "hang\n" << log;
  EXPECT_EQ(code, 0) << log;
  EXPECT_NE(log.find("(stopped early)"), std::string::npos) << log;
  const auto summary = ReadJson(out_ / "summary.json");
  const int processed = summary["frames_processed"];
  EXPECT_GE(processed, 3);
  EXPECT_LT(processed, 100 * kFrames);
  EXPECT_EQ(summary["frames_failed"], 0);
  EXPECT_EQ(Lines(out_ / "frames.csv").size(), static_cast<size_t>(processed + 1));
  EXPECT_GT(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), 0u);
  EXPECT_GT(io::ReadMeshOff(out_ / "mesh.off").num_triangles(), 0u);
}

// Whether the process `pid` has a handler installed for SIGINT (the SigCgt mask of /proc/PID/status).
bool CatchesSigint(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1u;
  }
  return false;
}

TEST_F(RunFaults, SecondSigintEndsTheProcessAtOnce) {
  const pid_t pid = Start(" --set input.loops=100");
  ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", 3, kRunTimeoutS)) << Log();
  ASSERT_TRUE(CatchesSigint(pid)) << "semap run should catch SIGINT while it runs";
  ASSERT_EQ(kill(pid, SIGINT), 0);
  // The first signal's handler asks the pipeline to stop and puts the default action back: once it has run,
  // a second Ctrl-C must end the process at once instead of waiting for the frames in flight.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kRunTimeoutS);
  while (CatchesSigint(pid) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(kill(pid, SIGINT), 0);
  const int code = Wait(pid, kRunTimeoutS);
  ASSERT_NE(code, -1) << "hang\n" << Log();
  EXPECT_EQ(code, -1000 - SIGINT) << "the second SIGINT should end the process\n" << Log();
}

}  // namespace
}  // namespace semap::tools
