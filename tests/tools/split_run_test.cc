// A split run in one process, the transport in memory: depth nodes (RunDepthNode) publish a generated
// street's depth frames, a map node (RunMapNode) maps them. Its mesh.ply equals the single-process run's
// byte for byte when nothing is lost; lost datagrams, a node that dies, a map node that starts late, foreign
// and malformed messages and a mismatched configuration each cost what they must and no more.
#include "app/split/split_run.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/config/config.h"
#include "app/run/stream_run.h"
#include "semap_lcm/depth_frame_part_t.hpp"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::app {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 12;

using Datagrams = std::vector<io::EncodedMessage>;

// The frame a datagram belongs to (its LCM header).
std::int64_t FrameOf(const io::EncodedMessage& d) {
  semap_lcm::depth_frame_part_t part;
  EXPECT_GE(part.decode(d.data(), 0, static_cast<int>(d.size())), 0);
  return part.frame_id;
}

class SplitRun : public ::testing::Test {
 protected:
  static fs::path Sequence() { return test::ProcessTempRoot() / "SplitRun_sequence"; }
  static void SetUpTestSuite() {
    fs::remove_all(Sequence());
    const test::CliRun r = test::RunSemap("synth --preset urban --frames " + std::to_string(kFrames) +
                                          " --seed 4 --out " + Sequence().string() + test::kSmallSynth);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }

  static Config MakeConfig(const fs::path& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> o = {"output.dir=" + out.string(), "simplify.method=PS", "split.wait_s=0.2",
                                  "split.idle_end_s=0.5", "split.first_frame_timeout_s=0.5"};
    o.insert(o.end(), extra.begin(), extra.end());
    return LoadConfig("", o);
  }
  static StreamRunRequest Request() {
    StreamRunRequest r;
    r.dataset = Sequence().string();
    r.progress_s.reset();
    r.lcm = RunOutputs::Lcm::kOff;
    return r;
  }

  // The datagrams depth node `share` publishes.
  static Datagrams DepthNode(const fs::path& out, FrameShare share, std::vector<std::string> extra = {},
                             const std::string& name = "depth") {
    Datagrams sent;
    std::mutex m;
    const StreamRunResult r = RunDepthNode(MakeConfig(out, std::move(extra)), Request(), share, name,
                                           [&](const io::EncodedMessage& d) {
                                             std::lock_guard<std::mutex> lock(m);
                                             sent.push_back(d);
                                           });
    EXPECT_EQ(r.outcome, StreamRunOutcome::kDone);
    EXPECT_FALSE(fs::exists(out / "mesh.ply"));  // a depth node has no map
    return sent;
  }

  // The map node's run on `datagrams`, all received before it starts.
  static StreamRunResult MapNode(const fs::path& out, const Datagrams& datagrams,
                                 std::shared_ptr<ReceivedFrames>* frames_out = nullptr) {
    const Config config = MakeConfig(out);
    auto frames =
        std::make_shared<ReceivedFrames>(config.split, DepthConfigFingerprint(config), SteadyClock().NowS());
    for (const auto& d : datagrams) frames->Add(d.data(), d.size(), SteadyClock().NowS());
    if (frames_out) *frames_out = frames;
    return RunMapNode(config, Request(), frames);
  }

  static nlohmann::json Summary(const fs::path& out) {
    return nlohmann::json::parse(std::ifstream(out / "summary.json"));
  }
  // The frame ids of frames.csv's rows.
  static std::set<std::int64_t> Integrated(const fs::path& out) {
    std::set<std::int64_t> ids;
    const std::vector<std::string> rows = test::NonEmptyLines(out / "frames.csv");
    for (size_t i = 1; i < rows.size(); ++i) ids.insert(std::stoll(test::CsvCells(rows[i]).at(0)));
    return ids;
  }
  static std::int64_t DroppedLost(const fs::path& out) {
    return Summary(out)["dropped_by_reason"]["lost"].get<std::int64_t>();
  }

  // The single-process run's mesh.ply.
  static const std::string& SingleMesh() {
    static const std::string mesh = [] {
      const fs::path out = test::ProcessTempRoot() / "SplitRun_single";
      const StreamRunResult r = StreamRun(MakeConfig(out), Request());
      EXPECT_EQ(r.outcome, StreamRunOutcome::kDone);
      return test::ReadFile(out / "mesh.ply");
    }();
    return mesh;
  }
  static const Datagrams& OneNode() {
    static const Datagrams d = DepthNode(test::ProcessTempRoot() / "SplitRun_node", FrameShare{0, 1});
    return d;
  }

  fs::path dir_ = test::TempDir();
};

TEST_F(SplitRun, TheMapNodesMeshEqualsTheSingleProcessRunsByteForByte) {
  ASSERT_FALSE(SingleMesh().empty());
  ASSERT_GT(OneNode().size(), static_cast<size_t>(kFrames));  // frames in several datagrams
  const StreamRunResult r = MapNode(dir_, OneNode());
  ASSERT_EQ(r.outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(test::ReadFile(dir_ / "mesh.ply"), SingleMesh());
  EXPECT_EQ(Integrated(dir_).size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(DroppedLost(dir_), 0);
}

TEST_F(SplitRun, TwoDepthNodesGiveTheSameMesh) {
  Datagrams both = DepthNode(dir_ / "a", FrameShare{0, 2}, {}, "a");
  const Datagrams b = DepthNode(dir_ / "b", FrameShare{1, 2}, {}, "b");
  std::set<std::int64_t> from_a;
  for (const auto& d : both) from_a.insert(FrameOf(d));
  EXPECT_EQ(from_a, (std::set<std::int64_t>{0, 2, 4, 6, 8, 10}));
  both.insert(both.end(), b.begin(), b.end());
  ASSERT_EQ(MapNode(dir_ / "map", both).outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(test::ReadFile(dir_ / "map" / "mesh.ply"), SingleMesh());
}

TEST_F(SplitRun, FivePercentOfDatagramsLostCostTheirFramesOnly) {
  std::mt19937 rng(11);
  std::bernoulli_distribution drop(0.05);
  Datagrams kept;
  std::set<std::int64_t> hit;
  for (const auto& d : OneNode()) {
    if (drop(rng)) {
      hit.insert(FrameOf(d));
    } else {
      kept.push_back(d);
    }
  }
  ASSERT_FALSE(hit.empty()) << "the seed drops no datagram";
  ASSERT_LT(hit.size(), static_cast<size_t>(kFrames));
  ASSERT_EQ(MapNode(dir_, kept).outcome, StreamRunOutcome::kDone);
  std::set<std::int64_t> expected;
  for (std::int64_t id = 0; id < kFrames; ++id)
    if (!hit.count(id)) expected.insert(id);
  EXPECT_EQ(Integrated(dir_), expected);
  EXPECT_EQ(DroppedLost(dir_), static_cast<std::int64_t>(hit.size()));
  std::set<std::int64_t> lost;
  for (const std::string& line : test::NonEmptyLines(dir_ / "errors.jsonl")) {
    const auto e = nlohmann::json::parse(line);
    EXPECT_EQ(e["dropped"], "lost") << line;
    lost.insert(e["frame_id"].get<std::int64_t>());
  }
  EXPECT_EQ(lost, hit);
}

TEST_F(SplitRun, WhenADepthNodeDiesTheOthersFramesStillArrive) {
  Datagrams all = DepthNode(dir_ / "a", FrameShare{0, 2}, {}, "a");
  for (const auto& d : DepthNode(dir_ / "b", FrameShare{1, 2}, {}, "b"))
    if (FrameOf(d) < 6) all.push_back(d);  // node b died after frame 5
  ASSERT_EQ(MapNode(dir_ / "map", all).outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(Integrated(dir_ / "map"), (std::set<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 8, 10}));
  EXPECT_EQ(DroppedLost(dir_ / "map"), 3);  // 7, 9, 11
}

TEST_F(SplitRun, AMapNodeStartedLateBeginsAtTheNextFrame) {
  Datagrams late;
  for (const auto& d : OneNode())
    if (FrameOf(d) >= 4) late.push_back(d);
  ASSERT_EQ(MapNode(dir_, late).outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(Integrated(dir_), (std::set<std::int64_t>{4, 5, 6, 7, 8, 9, 10, 11}));
  EXPECT_EQ(DroppedLost(dir_), 0);
}

TEST_F(SplitRun, ForeignAndMalformedMessagesAreCountedAndChangeNothing) {
  const Datagrams foreign = DepthNode(dir_ / "other", FrameShare{0, 1}, {"split.run_id=9"});
  Datagrams mixed;
  std::mt19937 rng(3);
  for (size_t i = 0; i < OneNode().size(); ++i) {
    mixed.push_back(OneNode()[i]);
    if (i < foreign.size()) mixed.push_back(foreign[i]);
    io::EncodedMessage junk = OneNode()[i];
    junk.resize(junk.size() / 2);
    mixed.push_back(junk);
    junk.assign(std::uniform_int_distribution<size_t>(1, 200)(rng), 0xab);
    mixed.push_back(junk);
  }
  std::shared_ptr<ReceivedFrames> frames;
  ASSERT_EQ(MapNode(dir_ / "map", mixed, &frames).outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(test::ReadFile(dir_ / "map" / "mesh.ply"), SingleMesh());
  const ReceivedFrames::Counters c = frames->counters();
  EXPECT_EQ(c.parts.foreign_run, static_cast<std::int64_t>(std::min(foreign.size(), OneNode().size())));
  EXPECT_GE(c.parts.malformed, static_cast<std::int64_t>(OneNode().size()));
}

TEST_F(SplitRun, ADepthNodeWithAnotherConfigurationIsRefusedByName) {
  const Datagrams other = DepthNode(dir_ / "other", FrameShare{0, 1}, {"depth.num_disparities=64"}, "cam-b");
  std::shared_ptr<ReceivedFrames> frames;
  const StreamRunResult r = MapNode(dir_ / "map", other, &frames);
  EXPECT_EQ(r.outcome, StreamRunOutcome::kNothingMapped);
  EXPECT_EQ(frames->counters().parts.refused, static_cast<std::int64_t>(other.size()));
  EXPECT_EQ(frames->counters().frames, 0);
  const std::vector<std::string> refusals = frames->Refusals();
  ASSERT_EQ(refusals.size(), 1u);  // once per node and reason
  EXPECT_NE(refusals.front().find("cam-b"), std::string::npos) << refusals.front();
  EXPECT_NE(refusals.front().find("config"), std::string::npos) << refusals.front();
}

TEST_F(SplitRun, AStopRequestEndsAMapNodeThatWaitsForFrames) {
  Config config = MakeConfig(dir_, {"split.first_frame_timeout_s=600"});
  auto frames =
      std::make_shared<ReceivedFrames>(config.split, DepthConfigFingerprint(config), SteadyClock().NowS());
  StreamRunRequest request = Request();
  std::thread stopper;
  request.on_running = [&](Pipeline* p) {
    if (p)
      stopper = std::thread([p] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        p->RequestStop();
      });
  };
  const auto t0 = std::chrono::steady_clock::now();
  const StreamRunResult r = RunMapNode(config, request, frames);
  stopper.join();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 60.0);
  EXPECT_TRUE(r.summary.stopped_early);
  EXPECT_EQ(r.outcome, StreamRunOutcome::kNothingMapped);  // no frame arrived
}

// A copy of the generated sequence (KITTI raw layout) whose cameras have another focal length: every
// occurrence of P_rect_02's fx in calib_cam_to_cam.txt replaced.
fs::path WithOtherFocalLength(const fs::path& sequence, const fs::path& to) {
  fs::copy(sequence, to, fs::copy_options::recursive);
  for (const auto& entry : fs::recursive_directory_iterator(to)) {
    if (entry.path().filename() != "calib_cam_to_cam.txt") continue;
    std::string text = test::ReadFile(entry.path());
    const size_t at = text.find("P_rect_02:");
    EXPECT_NE(at, std::string::npos);
    std::istringstream values(text.substr(at + std::string("P_rect_02:").size()));
    std::string fx;
    values >> fx;
    for (size_t p = text.find(fx); p != std::string::npos; p = text.find(fx, p + 1)) {
      text.replace(p, fx.size(), "7.500000000000e+02");
    }
    std::ofstream(entry.path()) << text;
  }
  return to;
}

TEST_F(SplitRun, ADepthNodeWithAnotherCalibrationIsRefusedByName) {
  Datagrams mixed = DepthNode(dir_ / "a", FrameShare{0, 2}, {}, "a");  // its calibration is the run's
  Datagrams other;
  {
    const fs::path sequence = WithOtherFocalLength(Sequence(), dir_ / "other_sequence");
    std::mutex m;
    StreamRunRequest request = Request();
    request.dataset = sequence.string();
    RunDepthNode(MakeConfig(dir_ / "b"), request, FrameShare{1, 2}, "cam-b",
                 [&](const io::EncodedMessage& d) {
                   std::lock_guard<std::mutex> lock(m);
                   other.push_back(d);
                 });
  }
  ASSERT_FALSE(other.empty());
  mixed.insert(mixed.end(), other.begin(), other.end());
  std::shared_ptr<ReceivedFrames> frames;
  ASSERT_EQ(MapNode(dir_ / "map", mixed, &frames).outcome, StreamRunOutcome::kDone);
  EXPECT_EQ(Integrated(dir_ / "map"), (std::set<std::int64_t>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(DroppedLost(dir_ / "map"), 6);
  EXPECT_EQ(frames->counters().parts.refused, static_cast<std::int64_t>(other.size()));
  const std::vector<std::string> refusals = frames->Refusals();
  ASSERT_FALSE(refusals.empty());
  EXPECT_NE(refusals.front().find("cam-b"), std::string::npos) << refusals.front();
}

}  // namespace
}  // namespace semap::app
