// The map node's frame order (ReceivedFrames) on datagrams encoded as depth nodes encode them, with time
// passed in: frames out in id order, a missing frame given up split.wait_s after a later one arrived, the
// run started at the first whole frame, ended when nothing arrives, and foreign, malformed and mismatched
// messages kept out.
#include "app/split/received_frames.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "app/split/depth_node.h"

namespace semap::app {
namespace {

constexpr std::int64_t kRun = 7;
constexpr std::int64_t kConfig = 1234;
constexpr int kFrames = 8;

SplitOptions Options() {
  SplitOptions o;
  o.run_id = static_cast<int>(kRun);
  o.wait_s = 1.0;
  o.idle_end_s = 5.0;
  o.first_frame_timeout_s = 30.0;
  return o;
}

StereoCalibration Calibration() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 100.0;
  c.cx_px = 32.0;
  c.cy_px = 24.0;
  c.baseline_m = 0.5;
  c.width_px = 64;
  c.height_px = 48;
  return c;
}

// Frame `id` of a kFrames-frame sequence, with random pixels (every frame differs).
io::DepthFrameMessage Message(std::int64_t id) {
  io::DepthFrameMessage m;
  m.frame_id = id;
  m.timestamp_s = 0.1 * static_cast<double>(id);
  m.sensed_unix_s = 1.7e9 + m.timestamp_s;
  m.first_frame_id = 0;
  m.sequence_frames = kFrames;
  m.calibration = Calibration();
  m.world_from_cam = Pose3d(Eigen::Translation3d(0.0, 0.0, static_cast<double>(id)));
  cv::RNG rng(static_cast<std::uint64_t>(id + 1));
  m.left.create(48, 64, CV_8UC3);
  rng.fill(m.left, cv::RNG::UNIFORM, 0, 256);
  m.disparity_px.create(48, 64, CV_32F);
  rng.fill(m.disparity_px, cv::RNG::UNIFORM, 0.0, 64.0);
  m.confidence = cv::Mat(48, 64, CV_32F, cv::Scalar(1.0f));
  m.labels.create(48, 64, CV_8UC1);
  rng.fill(m.labels, cv::RNG::UNIFORM, 0, 20);
  return m;
}

// Small datagrams, so that every frame comes in several parts.
std::vector<io::EncodedMessage> Datagrams(std::int64_t id, std::int64_t run = kRun,
                                          std::int64_t config = kConfig,
                                          const std::string& node = "depth-0") {
  io::DepthFrameOptions o;
  o.max_message_bytes = 4096;
  return io::DepthFrameSender(o, run, config, node).Encode(Message(id));
}

class Order : public ::testing::Test {
 protected:
  void Add(std::int64_t id, double now_s) {
    for (const auto& d : Datagrams(id)) frames_.Add(d.data(), d.size(), now_s);
  }
  // Polls at `now_s` until it has no frame: the ids it gave, then kWait or kEnd as the last element (-1, -2).
  std::vector<std::int64_t> Take(double now_s) {
    std::vector<std::int64_t> ids;
    Frame f;
    while (true) {
      const ReceivedFrames::Next n = frames_.Poll(now_s, &f);
      if (n == ReceivedFrames::Next::kFrame) {
        ids.push_back(f.id);
        continue;
      }
      ids.push_back(n == ReceivedFrames::Next::kWait ? -1 : -2);
      return ids;
    }
  }
  std::vector<std::int64_t> LostIds() {
    std::vector<std::int64_t> ids;
    for (const auto& l : frames_.TakeLost()) ids.push_back(l.frame_id);
    return ids;
  }
  ReceivedFrames frames_{Options(), kConfig, 0.0};
};

using Ids = std::vector<std::int64_t>;

TEST_F(Order, FramesComeOutInIdOrderWithTheirDepthWhateverOrderTheyArriveIn) {
  for (std::int64_t id : {1, 0, 3, 2}) Add(id, 0.5);
  EXPECT_EQ(Take(0.5), (Ids{0, 1, 2, 3, -1}));
  for (std::int64_t id : {5, 4, 7, 6}) Add(id, 0.6);
  Frame f;
  ASSERT_EQ(frames_.Poll(0.6, &f), ReceivedFrames::Next::kFrame);
  const io::DepthFrameMessage m = Message(4);
  EXPECT_EQ(f.id, 4);
  ASSERT_TRUE(f.depth);
  EXPECT_EQ(cv::norm(f.depth->disparity_px, m.disparity_px, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(f.depth->labels, m.labels, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(f.left, m.left, cv::NORM_INF), 0.0);
  EXPECT_TRUE(f.right.empty());
  EXPECT_DOUBLE_EQ(f.sensed_unix_s, m.sensed_unix_s);
  ASSERT_TRUE(f.world_from_cam);
  EXPECT_TRUE(f.world_from_cam->isApprox(*m.world_from_cam));
  EXPECT_EQ(Take(0.6), (Ids{5, 6, 7, -2}));  // the sequence's last frame: the end
  EXPECT_TRUE(LostIds().empty());
}

TEST_F(Order, AMissingFrameIsGivenUpOnlyAfterTheWaitBehindALaterOne) {
  Add(0, 0.0);
  Add(2, 1.0);  // frame 1 is late from here on
  EXPECT_EQ(Take(1.5), (Ids{0, -1}));
  EXPECT_TRUE(LostIds().empty());
  EXPECT_EQ(Take(2.0), (Ids{2, -1}));  // waited split.wait_s = 1 s: 1 is lost
  EXPECT_EQ(LostIds(), (Ids{1}));
  Add(1, 2.1);  // too late now: dropped part by part
  EXPECT_GT(frames_.counters().parts.late, 0);
  EXPECT_EQ(frames_.counters().lost, 1);
  EXPECT_EQ(Take(2.1), (Ids{-1}));
}

TEST_F(Order, AFrameMissingOnePartNeverCompletesAndOnlyItIsLost) {
  Add(0, 0.0);
  std::vector<io::EncodedMessage> parts = Datagrams(1);
  ASSERT_GE(parts.size(), 2u);
  parts.erase(parts.begin() + 1);
  for (const auto& d : parts) frames_.Add(d.data(), d.size(), 0.1);
  Add(2, 0.2);
  Add(3, 0.2);
  EXPECT_EQ(Take(0.5), (Ids{0, -1}));
  EXPECT_EQ(Take(1.3), (Ids{2, 3, -1}));
  EXPECT_EQ(LostIds(), (Ids{1}));
  EXPECT_EQ(frames_.counters().frames, 3);
}

TEST_F(Order, AFrameItsNodeAnnouncedDroppedIsLostWithoutTheWait) {
  io::DepthFrameOptions o;
  o.max_message_bytes = 4096;
  const io::EncodedMessage notice =
      io::DepthFrameSender(o, kRun, kConfig, "depth-0").EncodeDropped(1, 0.1, 0, kFrames);
  Add(0, 0.0);
  frames_.Add(notice.data(), notice.size(), 0.0);
  Add(2, 0.0);
  EXPECT_EQ(Take(0.0), (Ids{0, 2, -1}));  // no split.wait_s for frame 1
  EXPECT_EQ(LostIds(), (Ids{1}));
}

TEST_F(Order, ALateMapNodeStartsAtTheLowestWholeFrameOnceTheWaitHasPassed) {
  for (std::int64_t id : {5, 6, 4, 7}) Add(id, 1.0);
  Add(3, 1.5);                      // another node's earlier frame, still in time
  EXPECT_EQ(Take(1.9), (Ids{-1}));  // split.wait_s after the first whole frame: not yet
  EXPECT_EQ(Take(2.0), (Ids{3, 4, 5, 6, 7, -2}));
  EXPECT_TRUE(LostIds().empty());  // 0..2 were before this node's start, not lost
  EXPECT_EQ(frames_.counters().late, 0);
}

TEST_F(Order, TheSequencesFirstFrameStartsTheRunAtOnce) {
  Add(0, 1.0);
  EXPECT_EQ(Take(1.0), (Ids{0, -1}));
  Add(2, 1.1);
  Add(1, 1.2);
  EXPECT_EQ(Take(1.2), (Ids{1, 2, -1}));
}

TEST_F(Order, WhenNothingArrivesTheRunEndsAndTheRestIsLost) {
  Add(0, 0.0);
  Add(1, 0.0);
  EXPECT_EQ(Take(4.9), (Ids{0, 1, -1}));
  EXPECT_EQ(Take(5.0), (Ids{-2}));  // split.idle_end_s after the last part
  EXPECT_EQ(LostIds(), (Ids{2, 3, 4, 5, 6, 7}));
}

TEST_F(Order, NoFrameAtAllEndsAfterTheFirstFrameTimeout) {
  EXPECT_EQ(Take(29.0), (Ids{-1}));
  EXPECT_EQ(Take(30.0), (Ids{-2}));
  EXPECT_TRUE(LostIds().empty());
  EXPECT_EQ(frames_.counters().frames, 0);
}

TEST_F(Order, ForeignMalformedAndMismatchedMessagesAreCountedAndSkipped) {
  for (const auto& d : Datagrams(0, /*run=*/kRun + 1)) frames_.Add(d.data(), d.size(), 0.0);
  for (const auto& d : Datagrams(0, kRun, /*config=*/kConfig + 1, "cam-b"))
    frames_.Add(d.data(), d.size(), 0.0);
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    io::EncodedMessage junk = Datagrams(0).front();
    junk.resize(std::uniform_int_distribution<size_t>(0, junk.size())(rng));
    if (!junk.empty()) junk[std::uniform_int_distribution<size_t>(0, junk.size() - 1)(rng)] ^= 0x5a;
    frames_.Add(junk.data(), junk.size(), 0.0);
  }
  EXPECT_EQ(Take(0.0), (Ids{-1}));  // nothing of this run arrived whole
  const ReceivedFrames::Counters c = frames_.counters();
  EXPECT_GT(c.parts.foreign_run, 0);
  EXPECT_GT(c.parts.refused, 0);
  EXPECT_GT(c.parts.malformed, 0);
  const std::vector<std::string> refusals = frames_.TakeRefusals();
  ASSERT_FALSE(refusals.empty());
  EXPECT_NE(refusals.front().find("cam-b"), std::string::npos) << refusals.front();
  // The run's own frames still go through.
  Add(0, 0.1);
  EXPECT_EQ(Take(0.1), (Ids{0, -1}));
}

TEST(FrameShare, ParsesIOverNAndRefusesNonsenseByName) {
  const FrameShare s = ParseFrameShare("1/3");
  EXPECT_EQ(s.index, 1);
  EXPECT_EQ(s.count, 3);
  EXPECT_TRUE(s.Takes(4));
  EXPECT_FALSE(s.Takes(3));
  for (const char* bad : {"3/3", "-1/2", "1", "a/2", "1/0", "1/2x"}) {
    try {
      ParseFrameShare(bad);
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace semap::app
