// `semap lcm-mesh` as a user meets it on damaged logs: a clear error and a non-zero exit, or the damage
// skipped and reported, never a crash; an empty or unusable log is never an empty mesh with exit 0.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <sstream>

#include "io/lcm/lcm_log.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/io/lcm/lcm_test_mesh.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

using io::LcmLogEvent;

// A small run's mesh messages: a few frames, then the index of the run's end.
std::vector<LcmLogEvent> RunEvents() {
  test::EvolvingMesh source(2);
  io::MeshBlockSender sender(8.0, 4096, 5);
  std::vector<LcmLogEvent> out;
  const auto add = [&](const char* channel, std::vector<std::uint8_t> data) {
    const auto n = static_cast<std::int64_t>(out.size());
    out.push_back({n, 1000 * n, channel, std::move(data)});
  };
  for (int frame = 0; frame < 3; ++frame) {
    for (auto& m : sender.Apply(source.Step(frame))) add("SEMAP_MESH_BLOCK", std::move(m));
  }
  for (auto& m : sender.Index(0)) add("SEMAP_MESH_END", std::move(m));
  return out;
}

std::string Bytes(const std::vector<LcmLogEvent>& events) {
  std::ostringstream os;
  for (const auto& e : events) io::WriteLcmLogEvent(os, e);
  return os.str();
}

class LcmMeshCommand : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::TempDir(); }
  std::filesystem::path Log(const std::string& name, const std::string& bytes) {
    const auto path = dir_ / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  test::CliRun Rebuild(const std::filesystem::path& log, const std::string& extra = "") {
    return test::RunSemap("lcm-mesh " + log.string() + " --out " + (dir_ / "mesh.ply").string() + extra);
  }
  bool Wrote() const { return std::filesystem::exists(dir_ / "mesh.ply"); }
  std::filesystem::path dir_;
};

TEST_F(LcmMeshCommand, GoodLogIsRebuilt) {
  const auto r = Rebuild(Log("good.lcmlog", Bytes(RunEvents())));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("run ended")) << r.output;
  EXPECT_GT(io::ReadMeshPly(dir_ / "mesh.ply").num_triangles(), 10u);
}

TEST_F(LcmMeshCommand, EmptyOrForeignLogIsAnError) {
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"empty.lcmlog", ""}, {"text.lcmlog", std::string(200, 'x')}}) {
    const auto r = Rebuild(Log(name, bytes));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(r.Has(name)) << r.output;
    EXPECT_FALSE(Wrote());
  }
  const auto r = Rebuild(dir_ / "missing.lcmlog");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("no such LCM log file")) << r.output;
}

TEST_F(LcmMeshCommand, EventLengthOf0x7fffffffIsSkipped) {
  auto events = RunEvents();
  std::string bytes = Bytes({events[0]});
  for (int i : {24, 25, 26, 27}) bytes[i] = static_cast<char>(i == 24 ? 0x7f : 0xff);
  // Alone: no event at all.
  auto r = Rebuild(Log("only.lcmlog", bytes));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("not an LCM log")) << r.output;
  // Before the other events: skipped, reported, the rest used.
  events.erase(events.begin());
  r = Rebuild(Log("first.lcmlog", bytes + Bytes(events)));
  EXPECT_TRUE(r.Has("data length 2147483647")) << r.output;
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
}

TEST_F(LcmMeshCommand, TruncatedLogIsReported) {
  const std::string whole = Bytes(RunEvents());
  const auto r = Rebuild(Log("cut.lcmlog", whole.substr(0, whole.size() * 2 / 3)));
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
  EXPECT_TRUE(r.Has("bytes skipped")) << r.output;
  EXPECT_TRUE(r.Has("not seen to end")) << r.output;
}

TEST_F(LcmMeshCommand, WrongPrefixNamesTheChannels) {
  auto events = RunEvents();
  for (auto& e : events) e.channel = "OTHER_" + e.channel.substr(6);
  const auto log = Log("other.lcmlog", Bytes(events));
  auto r = Rebuild(log);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("OTHER_MESH_BLOCK")) << r.output;
  r = Rebuild(log, " --channel-prefix OTHER_");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(LcmMeshCommand, HugeCountsNanAndUnknownVerticesAreSkipped) {
  auto events = RunEvents();
  std::string error;
  const auto first = *io::DecodeMeshBlock(events[0].data.data(), events[0].data.size(), &error);
  const auto encode = [](const semap_lcm::mesh_block_t& m) {
    std::vector<std::uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
  };
  auto huge = events[0];
  for (int i : {12, 13, 14, 15}) huge.data[i] = i == 12 ? 0x7f : 0xff;  // num_vertices = 2^31 - 1
  auto nan = events[0], unknown = events[0];
  auto m = first;
  m.positions[0][0] = std::numeric_limits<float>::quiet_NaN();
  nan.data = encode(m);
  m = first;
  m.triangles[0][0] = 123456;
  unknown.data = encode(m);
  // Alone, none of them makes a mesh: an error naming why.
  auto r = Rebuild(Log("bad.lcmlog", Bytes({huge, nan, unknown})));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("no valid mesh message")) << r.output;
  EXPECT_FALSE(Wrote());
  // Among good messages: skipped and counted, the mesh written has finite vertices only.
  events.insert(events.begin(), {huge, nan, unknown});
  r = Rebuild(Log("mixed.lcmlog", Bytes(events)));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("3 mesh messages skipped as invalid")) << r.output;
  EXPECT_TRUE(r.Has("2147483647")) << r.output;
  EXPECT_TRUE(r.Has("non-finite")) << r.output;
  EXPECT_TRUE(r.Has("names vertex 123456")) << r.output;
  const Mesh mesh = io::ReadMeshPly(dir_ / "mesh.ply");  // semap's own reader accepts it
  for (const auto& v : mesh.vertices) ASSERT_TRUE(v.allFinite());
}

TEST_F(LcmMeshCommand, UsageErrors) {
  auto r = test::RunSemap("lcm-mesh --out " + (dir_ / "m.ply").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = test::RunSemap("lcm-mesh --live --url nosuchprovider://x --seconds 1 --out " +
                     (dir_ / "m.ply").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.Has("nosuchprovider://x")) << r.output;
}

}  // namespace
}  // namespace semap::tools
