// LCM logs read by semap's own reader, and damaged logs: bad event lengths, huge counts, unknown vertices,
// NaN, empty, truncated and foreign files give a clear error or a skipped and counted message, never a crash.
#include "io/lcm/lcm_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/file_error.h"
#include "tests/common/test_data.h"
#include "tests/io/lcm/lcm_test_mesh.h"

namespace semap::io {
namespace {

LcmLogEvent Event(std::int64_t n, const std::string& channel, std::vector<std::uint8_t> data) {
  return {n, 1000000 + 1000 * n, channel, std::move(data)};
}

// The events of a small published mesh (two frames, then the index of the run's end).
std::vector<LcmLogEvent> MeshEvents(const std::string& prefix = "SEMAP_") {
  test::EvolvingMesh source(8);
  MeshBlockSender sender(8.0, 4096, 77);
  std::vector<LcmLogEvent> out;
  for (int frame = 0; frame < 2; ++frame) {
    for (auto& m : sender.Apply(source.Step(frame))) {
      out.push_back(Event(static_cast<std::int64_t>(out.size()), prefix + "MESH_BLOCK", std::move(m)));
    }
  }
  for (auto& m : sender.Index(0)) {
    out.push_back(Event(static_cast<std::int64_t>(out.size()), prefix + "MESH_END", std::move(m)));
  }
  return out;
}

std::filesystem::path WriteLog(const std::string& name, const std::vector<LcmLogEvent>& events,
                               const std::string& tail = "") {
  const auto path = test::TempDir() / name;
  std::ofstream os(path, std::ios::binary);
  for (const auto& e : events) WriteLcmLogEvent(os, e);
  os << tail;
  return path;
}

std::string ErrorOf(const std::filesystem::path& log) {
  try {
    ReplayMeshLog(log);
  } catch (const FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a FileError for " << log;
  return "";
}

TEST(LcmLog, EventsRoundTrip) {
  const auto events = MeshEvents();
  const auto log = WriteLog("a.lcmlog", events);
  LcmLogReader reader(log);
  for (const auto& want : events) {
    const auto got = reader.Next();
    ASSERT_TRUE(got.has_value());
    EXPECT_EQ(got->eventnum, want.eventnum);
    EXPECT_EQ(got->timestamp_us, want.timestamp_us);
    EXPECT_EQ(got->channel, want.channel);
    EXPECT_EQ(got->data, want.data);
  }
  EXPECT_FALSE(reader.Next().has_value());
  EXPECT_TRUE(reader.problem().empty());
  const auto replay = ReplayMeshLog(log);
  EXPECT_GT(replay.mesh.num_triangles(), 10u);
  EXPECT_TRUE(replay.index_complete);
}

// An event header claiming 0x7fffffff bytes (liblcm's reader crashed on it) is skipped: reading resumes at
// the next sync word.
TEST(LcmLog, HugeEventLengthIsSkippedToTheNextEvent) {
  auto events = MeshEvents();
  std::ostringstream os;
  WriteLcmLogEvent(os, events[0]);
  std::string damaged = os.str();
  for (int i : {24, 25, 26, 27}) damaged[i] = static_cast<char>(i == 24 ? 0x7f : 0xff);
  const auto path = test::TempDir() / "huge.lcmlog";
  {
    std::ofstream out(path, std::ios::binary);
    out << damaged;
    for (size_t i = 1; i < events.size(); ++i) WriteLcmLogEvent(out, events[i]);
  }
  LcmLogReader reader(path);
  std::int64_t n = 0;
  while (reader.Next()) ++n;
  EXPECT_EQ(n, static_cast<std::int64_t>(events.size()) - 1);
  EXPECT_EQ(reader.damaged_headers(), 1);
  EXPECT_NE(reader.problem().find("data length 2147483647"), std::string::npos) << reader.problem();
  EXPECT_NE(reader.problem().find("at byte 0"), std::string::npos) << reader.problem();
  const auto replay = ReplayMeshLog(path);  // the rest is used
  EXPECT_GT(replay.mesh.num_triangles(), 0u);
  EXPECT_FALSE(replay.log_problem.empty());
}

// Found by fuzz_lcm_log: timestamps far apart overflowed a signed difference.
TEST(LcmLog, ExtremeTimestampsGiveAFiniteDuration) {
  auto events = MeshEvents();
  events.front().timestamp_us = std::numeric_limits<std::int64_t>::min();
  events.back().timestamp_us = std::numeric_limits<std::int64_t>::max();
  MeshReplayOptions options;
  options.join_after_s = 1.0;
  const auto replay = ReplayMeshLog(WriteLog("far.lcmlog", events), options);
  EXPECT_TRUE(std::isfinite(replay.duration_s));
  EXPECT_GT(replay.duration_s, 1e12);
}

TEST(LcmLog, TruncatedLogKeepsTheCompleteEvents) {
  const auto events = MeshEvents();
  std::ostringstream os;
  for (const auto& e : events) WriteLcmLogEvent(os, e);
  const std::string whole = os.str();
  const auto path = test::TempDir() / "cut.lcmlog";
  std::ofstream(path, std::ios::binary) << whole.substr(0, whole.size() - 10);
  const auto replay = ReplayMeshLog(path);
  EXPECT_EQ(replay.events, static_cast<std::int64_t>(events.size()) - 1);
  EXPECT_NE(replay.log_problem.find("data length"), std::string::npos) << replay.log_problem;
  EXPECT_FALSE(replay.blocks.run_ended);  // the last message was the one cut
}

TEST(LcmLog, EmptyForeignOrMissingLogIsAnErrorNamingThePath) {
  EXPECT_NE(ErrorOf("/no/such.lcmlog").find("no such LCM log"), std::string::npos);
  const auto empty = WriteLog("empty.lcmlog", {});
  EXPECT_NE(ErrorOf(empty).find("empty.lcmlog: empty LCM log"), std::string::npos);
  const auto junk = test::TempDir() / "junk.lcmlog";
  std::ofstream(junk) << "this is not an LCM log, though long enough to hold a header or two";
  EXPECT_NE(ErrorOf(junk).find("junk.lcmlog: not an LCM log"), std::string::npos);
}

TEST(LcmLog, WrongPrefixNamesTheChannelsThere) {
  const auto log = WriteLog("other.lcmlog", MeshEvents("ROBOT_"));
  const auto error = ErrorOf(log);
  EXPECT_NE(error.find("no valid mesh message on SEMAP_MESH_BLOCK"), std::string::npos) << error;
  EXPECT_NE(error.find("ROBOT_MESH_BLOCK"), std::string::npos) << error;
  MeshReplayOptions options;
  options.channel_prefix = "ROBOT_";
  EXPECT_GT(ReplayMeshLog(log, options).mesh.num_triangles(), 0u);
}

// A message with a huge count, a NaN vertex or an unknown vertex is skipped and counted; the others are used.
TEST(LcmLog, InvalidMessagesAreSkippedAndCounted) {
  auto events = MeshEvents();
  const auto good = ReplayMeshLog(WriteLog("good.lcmlog", events));
  std::string error;
  auto first = *DecodeMeshBlock(events[0].data.data(), events[0].data.size(), &error);
  std::vector<LcmLogEvent> bad;
  auto huge = events[0].data;
  for (int i : {12, 13, 14, 15}) huge[i] = i == 12 ? 0x7f : 0xff;  // num_vertices = 2^31 - 1
  bad.push_back(Event(100, "SEMAP_MESH_BLOCK", huge));
  const auto encode = [](const semap_lcm::mesh_block_t& m) {
    std::vector<std::uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
  };
  auto nan = first;
  nan.version += 100;  // would otherwise win over the good versions
  nan.positions[0][1] = std::numeric_limits<float>::quiet_NaN();
  bad.push_back(Event(101, "SEMAP_MESH_BLOCK", encode(nan)));
  auto unknown = first;
  unknown.version += 100;
  unknown.triangles[0][2] = 1 << 30;
  bad.push_back(Event(102, "SEMAP_MESH_BLOCK", encode(unknown)));
  bad.push_back(Event(103, "SEMAP_MESH_END", {1, 2, 3}));
  events.insert(events.begin() + 1, bad.begin(), bad.end());
  const auto replay = ReplayMeshLog(WriteLog("bad.lcmlog", events));
  EXPECT_EQ(replay.skipped, 4);
  ASSERT_EQ(replay.skipped_reasons.size(), 4u);
  EXPECT_NE(replay.skipped_reasons[0].find("event 100 on SEMAP_MESH_BLOCK"), std::string::npos);
  EXPECT_NE(replay.skipped_reasons[0].find("2147483647"), std::string::npos);
  EXPECT_NE(replay.skipped_reasons[1].find("non-finite"), std::string::npos);
  EXPECT_NE(replay.skipped_reasons[2].find("names vertex 1073741824"), std::string::npos);
  EXPECT_NE(replay.skipped_reasons[3].find("too short"), std::string::npos);
  EXPECT_EQ(test::Soup(replay.mesh), test::Soup(good.mesh));
  for (const auto& v : replay.mesh.vertices) ASSERT_TRUE(v.allFinite());
  // A log of nothing but invalid messages is an error that says why.
  error = ErrorOf(WriteLog("only_bad.lcmlog", bad));
  EXPECT_NE(error.find("no valid mesh message"), std::string::npos) << error;
  EXPECT_NE(error.find("2147483647"), std::string::npos) << error;
}

}  // namespace
}  // namespace semap::io
