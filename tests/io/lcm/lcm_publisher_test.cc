#include "io/lcm/lcm_publisher.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <random>
#include <set>

#include "engine/core/check.h"
#include "io/lcm/lcm_log.h"
#include "tests/common/test_data.h"
#include "tests/io/lcm/lcm_test_mesh.h"
#include "tests/io/lcm/log_filter.h"

namespace semap::io {
namespace {

// Triangles of `want` that `have` holds (as triangles by vertex positions).
double FractionHeld(const Mesh& have, const Mesh& want) {
  const auto h = test::Soup(have), w = test::Soup(want);
  std::vector<std::array<double, 9>> common;
  std::set_intersection(h.begin(), h.end(), w.begin(), w.end(), std::back_inserter(common));
  return w.empty() ? 1.0 : double(common.size()) / double(w.size());
}

// Publishes a randomly evolving mesh (with finalised parts) through a `file://` LCM provider (a real LCM log,
// no network), once per test suite; tests replay it whole or filtered.
class PublishedLog : public ::testing::Test {
 protected:
  static constexpr int kMaxMessage = 2048;

  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::TempDir());
    LcmOptions options;
    options.enabled = true;
    options.url = "file://" + Log().string() + "?mode=w";
    options.block_size_m = 8.0;
    options.max_message_bytes = kMaxMessage;
    options.resend_bytes_per_s = 5e6;
    test::EvolvingMesh source(3);
    {
      LcmPublisher publisher(options);
      for (int frame = 0; frame < 60; ++frame) {
        publisher.PublishMeshDelta(
            source.Step(frame));  // never blocks: deltas coalesce while the sender is busy
        publisher.PublishFrameStats(FrameStats{});
      }
      publisher.Flush();
      const auto c = publisher.counters();
      EXPECT_GE(c.mesh_messages, 1);
      EXPECT_EQ(c.send_failures, 0);
      EXPECT_LE(c.largest_message, kMaxMessage);
    }  // the closing rounds and the run's last message
    truth_ = new Mesh(source.truth().ToMesh());
  }
  static void TearDownTestSuite() {
    delete truth_;
    delete dir_;
  }
  static std::filesystem::path Log() { return *dir_ / "run.lcmlog"; }
  static std::filesystem::path Copy(const std::string& name) { return *dir_ / name; }

  static std::filesystem::path* dir_;
  static Mesh* truth_;
};
std::filesystem::path* PublishedLog::dir_ = nullptr;
Mesh* PublishedLog::truth_ = nullptr;

TEST_F(PublishedLog, ReplayRebuildsThePublishedMesh) {
  const auto replay = ReplayMeshLog(Log());
  EXPECT_EQ(test::Soup(replay.mesh), test::Soup(*truth_));
  ASSERT_TRUE(replay.mesh.IsConsistent());
  EXPECT_TRUE(replay.missing.empty()) << ::testing::PrintToString(replay.missing);
  EXPECT_TRUE(replay.index_complete);
  EXPECT_TRUE(replay.blocks.run_ended);
  EXPECT_EQ(replay.skipped, 0);
  EXPECT_GE(replay.other_events, 1);
  EXPECT_LE(replay.largest_message, kMaxMessage);
}

TEST_F(PublishedLog, SubscriberThatMissedTheFirstHalfConvergesAfterTheClosingRounds) {
  const std::int64_t half = test::CountEvents(Log()) / 2;
  test::FilterLog(Log(), Copy("late.lcmlog"), [&](std::int64_t i, const LcmLogEvent&) { return i >= half; });
  const auto replay = ReplayMeshLog(Copy("late.lcmlog"));
  EXPECT_EQ(test::Soup(replay.mesh), test::Soup(*truth_));
  EXPECT_TRUE(replay.missing.empty()) << ::testing::PrintToString(replay.missing);
}

TEST_F(PublishedLog, FivePercentLostMeshMessagesStillRebuildAlmostAll) {
  std::mt19937 rng(20);
  const auto dropped = test::FilterLog(Log(), Copy("lossy.lcmlog"), [&](std::int64_t, const LcmLogEvent& e) {
    return !test::IsMeshEvent(e) || rng() % 100 >= 5;
  });
  EXPECT_GT(dropped, 0);
  const auto replay = ReplayMeshLog(Copy("lossy.lcmlog"));
  const double held = FractionHeld(replay.mesh, *truth_);
  EXPECT_GE(held, 0.999);
  if (held < 1.0) {
    EXPECT_FALSE(replay.missing.empty()) << "incomplete, but no block named";
  }
}

// Every message of one block lost (all its versions and re-sends): the run's index names it.
TEST_F(PublishedLog, ABlockNeverReceivedIsNamed) {
  std::string lost;
  test::FilterLog(Log(), Copy("holed.lcmlog"), [&](std::int64_t, const LcmLogEvent& e) {
    if (!e.channel.ends_with("MESH_BLOCK")) return true;
    std::string error;
    const auto b = DecodeMeshBlock(e.data.data(), e.data.size(), &error);
    if (!b) return true;
    const std::string key = BlockKey{b->block[0], b->block[1], b->block[2], b->serial}.ToString();
    if (lost.empty() && b->serial == 0) lost = key;
    return key != lost;
  });
  ASSERT_FALSE(lost.empty());
  const auto replay = ReplayMeshLog(Copy("holed.lcmlog"));
  EXPECT_FALSE(replay.index_complete);
  ASSERT_EQ(replay.missing.size(), 1u) << ::testing::PrintToString(replay.missing);
  EXPECT_EQ(replay.missing[0].find(lost + ": never received"), 0u) << replay.missing[0];
}

// Mesh messages leave no faster than lcm.max_bytes_per_s, so that a burst never overruns a subscriber.
TEST(LcmPublisher, MeshMessagesAreSpacedAtTheCeiling) {
  LcmOptions options;
  options.url = "file://" + (test::TempDir() / "paced.lcmlog").string() + "?mode=w";
  options.max_message_bytes = 2048;
  options.max_bytes_per_s = 1.0e5;
  options.resend_bytes_per_s = 1.0e3;  // no re-send in the time this takes
  options.closing_rounds = 0;
  test::EvolvingMesh source(6);
  LcmPublisher publisher(options);
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 0; frame < 8; ++frame) publisher.PublishMeshDelta(source.Step(frame));
  publisher.Flush();
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto c = publisher.counters();
  ASSERT_GT(c.mesh_bytes, 5 * 2048);
  EXPECT_GE(elapsed, 0.9 * double(c.mesh_bytes - 2 * c.largest_message) / options.max_bytes_per_s);
}

TEST(LcmPublisher, InvalidUrlIsAClearError) {
  LcmOptions options;
  options.url = "nosuchprovider://nowhere";
  try {
    LcmPublisher p(options);
    FAIL() << "expected LcmError";
  } catch (const LcmError& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://nowhere"), std::string::npos);
  }
}

TEST(LcmPublisher, OptionsAreChecked) {
  const auto invalid = [](auto edit) {
    LcmOptions o;
    edit(o);
    EXPECT_THROW(o.Check(), InvalidOption);
  };
  invalid([](LcmOptions& o) { o.max_message_bytes = 100; });
  invalid([](LcmOptions& o) { o.block_size_m = 0.0; });
  invalid([](LcmOptions& o) { o.block_size_m = std::numeric_limits<double>::quiet_NaN(); });
  invalid([](LcmOptions& o) { o.resend_bytes_per_s = 0.0; });
  invalid([](LcmOptions& o) { o.max_bytes_per_s = o.resend_bytes_per_s / 2; });
  invalid([](LcmOptions& o) { o.closing_rounds = -1; });
  invalid([](LcmOptions& o) { o.closing_max_s = -1.0; });
  LcmOptions defaults;
  EXPECT_NO_THROW(defaults.Check());
  EXPECT_LE(defaults.max_message_bytes, 64 * 1024);
}

}  // namespace
}  // namespace semap::io
