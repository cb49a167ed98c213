// Faults while streaming, end to end through `semap run` on a small generated sequence that each test damages
// in its own copy: what the README's "Faults" table documents, checked one fault at a time. No run may crash
// or hang (every run is bounded by `timeout`; a hang is exit code 124).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

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
const std::string& kSmall = test::kSmallSynth;
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

// Whether the process `pid` has a handler installed for `signal` (the SigCgt mask of /proc/PID/status).
bool CatchesSignal(pid_t pid, int signal) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (signal - 1)) & 1u;
  }
  return false;
}

// The generated sequence (once per test binary) and each test's own copy of it.
class RunFaults : public ::testing::Test {
 protected:
  static fs::path Pristine() { return test::ProcessTempRoot() / "RunFaults_sequence"; }

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

  std::string Log() const { return test::ReadFile(dir_ / "run.log"); }

  // The run finished with `failed` frames skipped (the others processed), and wrote a mesh.
  void ExpectSkipped(const CliRun& r, const std::vector<std::int64_t>& failed) const {
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const auto summary = ReadJson(out_ / "summary.json");
    EXPECT_EQ(summary["frames_processed"], kFrames - static_cast<int>(failed.size())) << summary.dump();
    EXPECT_EQ(summary["frames_failed"], static_cast<int>(failed.size())) << summary.dump();
    EXPECT_EQ(Lines(out_ / "frames.csv").size(), static_cast<size_t>(kFrames - failed.size() + 1));
    const auto errors = Lines(out_ / "errors.jsonl");
    ASSERT_EQ(errors.size(), failed.size());
    for (size_t i = 0; i < failed.size(); ++i)
      EXPECT_EQ(nlohmann::json::parse(errors[i])["frame_id"], failed[i]);
    EXPECT_GT(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), 0u);
  }

  // The error recorded for the first skipped frame.
  nlohmann::json FirstError() const { return nlohmann::json::parse(Lines(out_ / "errors.jsonl").at(0)); }

  // The first `signal`'s handler asks the pipeline to stop and puts the default actions back: once it has
  // run, a second one must end the process at once instead of waiting for the frames in flight.
  void ExpectSecondSignalEndsTheProcessAtOnce(int signal) const {
    const pid_t pid = Start(" --set input.loops=100");
    ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", 3, kRunTimeoutS)) << Log();
    ASSERT_TRUE(CatchesSignal(pid, signal)) << "semap run should catch signal " << signal << " while it runs";
    ASSERT_EQ(kill(pid, signal), 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kRunTimeoutS);
    while (CatchesSignal(pid, signal) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_EQ(kill(pid, signal), 0);
    const int code = Wait(pid, kRunTimeoutS);
    ASSERT_NE(code, -1) << "hang\n" << Log();
    EXPECT_EQ(code, -1000 - signal) << "the second signal " << signal << " should end the process\n" << Log();
  }

  // With `scan` missing or unusable, the run (which does not read scans) processes every frame, and
  // `semap eval` leaves that frame out, counts it and names the file (and `problem`, when given).
  void ExpectScanLeftOutOfEvaluation(const fs::path& scan, const std::string& problem) const {
    ExpectSkipped(Run(), {});
    const CliRun eval =
        test::RunShell("timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) + " eval " +
                       (dir_ / "seq").string() + " --mesh " + (out_ / "mesh.ply").string());
    EXPECT_EQ(eval.exit_code, 0) << eval.output;
    EXPECT_TRUE(eval.Has(std::to_string(kFrames - 1) + " evaluated (" + std::to_string(kFrames - 1) +
                         " with Velodyne"))
        << eval.output;
    EXPECT_TRUE(eval.Has("1 frame(s) could not be read")) << eval.output;
    EXPECT_TRUE(eval.Has(scan.string())) << eval.output;
    EXPECT_TRUE(eval.Has(problem)) << eval.output;
  }

  // A long run sent `signal` after a few frames drains the frames in flight, writes the mesh so far and the
  // stats, says "(stopped early)" and exits 0.
  void ExpectStopsCleanlyOn(int signal, const std::string& extra = "") const {
    const pid_t pid = Start(" --set input.loops=100" + extra);
    ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", 3, kRunTimeoutS)) << Log();
    ASSERT_EQ(kill(pid, signal), 0);
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
  const fs::path scan = drive_ / "velodyne_points/data" / Frame(2, "bin");
  fs::remove(scan);
  ExpectScanLeftOutOfEvaluation(scan, "");
}

TEST_F(RunFaults, EmptyVelodyneScanIsAMissingScan) {
  // A 0-byte scan is not a frame with Velodyne (an empty reference would count as evaluated).
  const fs::path scan = drive_ / "velodyne_points/data" / Frame(2, "bin");
  test::TruncateFile(scan, 0);
  ExpectScanLeftOutOfEvaluation(scan, "Velodyne scan is empty");
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
  EXPECT_NE(e["error"].get<std::string>().find((drive_ / "oxts/data" / Frame(5, "txt")).string()),
            std::string::npos)
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

TEST_F(RunFaults, SigintStopsCleanlyWithTheMeshSoFar) { ExpectStopsCleanlyOn(SIGINT); }

TEST_F(RunFaults, SecondSigintEndsTheProcessAtOnce) { ExpectSecondSignalEndsTheProcessAtOnce(SIGINT); }

TEST_F(RunFaults, SecondSigtermEndsTheProcessAtOnce) { ExpectSecondSignalEndsTheProcessAtOnce(SIGTERM); }

// --- every way a run can end -------------------------------------------------------------------------------

TEST_F(RunFaults, SigtermStopsCleanlyWithTheMeshSoFar) {
  // What `timeout`, systemd and container runtimes send: the same as Ctrl-C.
  ExpectStopsCleanlyOn(SIGTERM);
}

TEST_F(RunFaults, SigtermWithEnetOnItsOwnThreadStopsCleanly) {
  // The segment thread (ENet on keyframes) drains with the frames in flight: none waits for ever.
  SEMAP_REQUIRE_SHARED("models/enet-cityscapes/enet-model.net");
  ExpectStopsCleanlyOn(SIGTERM,
                       " --set semantics.source=enet --set semantics.enet_every_frames=2"
                       " --set semantics.enet_input_width_px=256 --set semantics.enet_input_height_px=128"
                       " --set semantics.enet_model_path=" +
                           (test::SharedDir() / "models/enet-cityscapes/enet-model.net").string());
}

TEST_F(RunFaults, ClosedOutputPipeDoesNotKillTheRun) {
  // `semap run … 2>&1 | head -1`: the reader goes away after the first line; the run goes on to the end.
  const fs::path code = dir_ / "code";
  const CliRun r = test::RunShell("( timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) +
                                  " run " + (dir_ / "seq").string() + " --out " + out_.string() + kFast +
                                  "; echo $? > " + code.string() + " ) 2>&1 | head -n 1");
  EXPECT_EQ(test::ReadTextFile(code), "0\n") << "exit code of semap run (141 = killed by SIGPIPE)";
  EXPECT_EQ(ReadJson(out_ / "summary.json")["frames_processed"], kFrames);
  EXPECT_GT(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), 0u);
}

TEST_F(RunFaults, RerunKilledMidwayLeavesTheOldMeshWholeAndNoSummary) {
  ASSERT_EQ(Run().exit_code, 0);
  const size_t old_triangles = io::ReadMeshPly(out_ / "mesh.ply").num_triangles();
  const pid_t pid = Start(" --set input.loops=100");
  // More rows than the first run wrote: the new run is under way.
  ASSERT_TRUE(WaitForRows(pid, out_ / "frames.csv", kFrames + 3, kRunTimeoutS)) << Log();
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  Wait(pid, kRunTimeoutS);
  // summary.json is removed when a run starts and written last: its absence says the run did not finish.
  EXPECT_FALSE(fs::exists(out_ / "summary.json"));
  EXPECT_EQ(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), old_triangles);
  EXPECT_GT(io::ReadMeshOff(out_ / "mesh.off").num_triangles(), 0u);
}

TEST_F(RunFaults, FailedStartLeavesThePreviousRunsFilesAlone) {
  ASSERT_EQ(Run().exit_code, 0);
  std::vector<std::string> before;
  for (const char* name : {"frames.csv", "frames.jsonl", "errors.jsonl", "summary.json", "mesh.ply"}) {
    before.push_back(test::ReadTextFile(out_ / name));
  }
  const CliRun r = Run(" --lcm-url 'bogus://nowhere:1'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  size_t i = 0;
  for (const char* name : {"frames.csv", "frames.jsonl", "errors.jsonl", "summary.json", "mesh.ply"}) {
    EXPECT_EQ(test::ReadTextFile(out_ / name), before[i++]) << name;
  }
}

TEST_F(RunFaults, EvaluationFileThatCannotBeWrittenIsAnErrorNotWrote) {
  // eval.json cannot replace a folder of that name (as a full disk, the write fails): exit 1 naming it.
  fs::create_directories(out_ / "eval.json" / "x");
  const CliRun r = Run(" --eval");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has((out_ / "eval.json").string() + ": cannot rename")) << r.output;
  EXPECT_FALSE(r.Has("wrote " + (out_ / "eval_frames.csv").string() + " and")) << r.output;
  EXPECT_TRUE(fs::is_directory(out_ / "eval.json" / "x"));
}

TEST_F(RunFaults, UnwritableOutputFolderIsCaughtBeforeTheFirstFrameWithoutFrameStats) {
  test::WriteTextFile(dir_ / "file", "x");
  const fs::path out = dir_ / "file" / "out";
  const CliRun r = test::RunShell("timeout " + std::to_string(kRunTimeoutS) + " " + std::string(SEMAP_EXE) +
                                  " run " + (dir_ / "seq").string() + " --out " + out.string() + kFast +
                                  " --set output.frame_stats=false");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has(out.string())) << r.output;
  EXPECT_FALSE(r.Has("frames processed")) << r.output;
}

TEST_F(RunFaults, EveryFrameFailingIsAnErrorAndTheMissingCalibrationIsNamed) {
  // OXTS poses need calib_velo_to_cam.txt: without it every frame fails, naming the file.
  const fs::path velo = drive_.parent_path() / "calib_velo_to_cam.txt";
  ASSERT_TRUE(fs::remove(velo));
  const CliRun r = Run(" --eval");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("--eval: the mesh has no faces: nothing to evaluate")) << r.output;
  EXPECT_FALSE(r.Has("RMSE")) << r.output;
  EXPECT_TRUE(r.Has("no frame could be processed: all " + std::to_string(kFrames) + " frames failed"))
      << r.output;
  EXPECT_TRUE(r.Has(velo.string() + ": calibration file not found")) << r.output;
  EXPECT_EQ(Lines(out_ / "errors.jsonl").size(), static_cast<size_t>(kFrames));
  EXPECT_NE(FirstError()["error"].get<std::string>().find(velo.string()), std::string::npos);
}

TEST_F(RunFaults, ImplausiblePrincipalPointIsAnErrorBeforeAnyFrame) {
  const fs::path cam = drive_.parent_path() / "calib_cam_to_cam.txt";
  for (const char* typo : {"1e9", "6095593"}) {
    std::string text = test::ReadTextFile(cam);
    const auto line = text.find("P_rect_02:");
    ASSERT_NE(line, std::string::npos);
    std::istringstream in(text.substr(line + 10, text.find('\n', line) - line - 10));
    std::vector<std::string> v;
    for (std::string x; in >> x;) v.push_back(x);
    ASSERT_EQ(v.size(), 12u);
    v[2] = typo;  // cx
    std::string edited = text.substr(0, line) + "P_rect_02:";
    for (const auto& x : v) edited += " " + x;
    edited += text.substr(text.find('\n', line));
    const fs::path damaged = dir_ / "damaged_calib.txt";
    test::WriteTextFile(damaged, edited);
    fs::copy_file(damaged, cam, fs::copy_options::overwrite_existing);
    const CliRun r = Run();
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(r.Has(cam.string() + ": key 'P_rect_02': principal point cx =")) << r.output;
    EXPECT_FALSE(r.Has("frames processed")) << r.output;
    test::WriteTextFile(cam, text);
  }
}

TEST_F(RunFaults, FrameOfAnotherSizeThanTheCalibrationIsSkippedAndCounted) {
  const fs::path left = drive_ / "image_02/data" / Frame(3, "png");
  for (const char* cam : {"image_02", "image_03"}) {
    const fs::path path = drive_ / cam / "data" / Frame(3, "png");
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
    cv::Mat big;
    cv::resize(image, big, cv::Size(image.cols * 2, image.rows * 2));
    ASSERT_TRUE(cv::imwrite(path.string(), big));
  }
  ExpectSkipped(Run(), {3});
  const auto e = FirstError();
  EXPECT_EQ(e["stage"], "read");
  EXPECT_NE(
      e["error"].get<std::string>().find(left.string() + ": left image is 640x192 but the calibration is for "
                                                         "320x96"),
      std::string::npos)
      << e.dump();
}

TEST_F(RunFaults, LabelImageOfAnotherSizeIsResizedWithAWarning) {
  const fs::path label = drive_ / "semantic/data" / Frame(2, "png");
  const cv::Mat labels = cv::imread(label.string(), cv::IMREAD_UNCHANGED);
  cv::Mat small;
  cv::resize(labels, small, cv::Size(labels.cols / 2, labels.rows / 2), 0, 0, cv::INTER_NEAREST);
  ASSERT_TRUE(cv::imwrite(label.string(), small));
  const CliRun r = Run();
  ExpectSkipped(r, {});
  EXPECT_TRUE(r.Has("frame 2: label image 160x48 resized (nearest neighbour) to the image size 320x96"))
      << r.output;
  // semantics.size_mismatch: refuse makes it a skipped frame.
  const CliRun refused = Run(" --set semantics.size_mismatch=refuse");
  ExpectSkipped(refused, {2});
  EXPECT_NE(FirstError()["error"].get<std::string>().find("label image of frame 2 is 160x48"),
            std::string::npos)
      << FirstError().dump();
}

TEST_F(RunFaults, MissingLabelImageCostsNothingWithSemanticsSourceNone) {
  fs::remove(drive_ / "semantic/data" / Frame(4, "png"));
  ExpectSkipped(Run(" --set semantics.source=none"), {});
}

TEST_F(RunFaults, BadNumbersOnTheCommandLineAreRefusedNamingTheOption) {
  struct Case {
    std::string args;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {" --frames -5", {"--frames"}},
      {" --set map.sigma_free_m=.inf", {"map.sigma_free_m", "must be a finite number"}},
      {" --set map.sigma_free_m=.nan", {"map.sigma_free_m", "must be a finite number"}},
      {" --set pipeline.cpu_affinity=[0,1000]", {"pipeline.cpu_affinity", "no such CPU available"}},
  };
  for (const Case& c : cases) {
    const CliRun r = Run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    for (const auto& text : c.says) EXPECT_TRUE(r.Has(text)) << c.args << "\n" << r.output;
    EXPECT_FALSE(r.Has("frames processed")) << c.args << "\n" << r.output;
  }
}

TEST_F(RunFaults, LogAndErrorsGoToStderr) {
  const CliRun ok = test::RunShell("{ " + std::string(SEMAP_EXE) + " run " + (dir_ / "seq").string() +
                                   " --out " + out_.string() + kFast + " --frames 2 2>/dev/null; }");
  EXPECT_EQ(ok.exit_code, 0);
  EXPECT_EQ(ok.output, "");
  const CliRun bad = test::RunShell("{ " + std::string(SEMAP_EXE) + " run " + (dir_ / "none").string() +
                                    " --out " + out_.string() + " 2>/dev/null; }");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(bad.output, "");
  EXPECT_TRUE(test::RunSemap("run " + (dir_ / "none").string() + " --out " + out_.string()).Has("not found"));
}

}  // namespace
}  // namespace semap::tools
