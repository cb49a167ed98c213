#include "io/lcm/lcm_publisher.h"

#include <fstream>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "io/lcm/lcm_log.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

// A mesh over vertex ids; vertex id i sits at (i, 0.5 i, 1).
IdentifiedMesh MakeMesh(const std::vector<std::array<VertexId, 3>>& tris) {
  IdentifiedMesh m;
  std::map<VertexId, std::uint32_t> index;
  for (const auto& t : tris) {
    std::array<std::uint32_t, 3> local{};
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = index.emplace(t[k], static_cast<std::uint32_t>(m.vertex_ids.size()));
      if (inserted) {
        m.vertex_ids.push_back(t[k]);
        m.mesh.vertices.emplace_back(double(t[k]), 0.5 * double(t[k]), 1.0);
        m.mesh.labels.push_back(static_cast<Label>(t[k] % 20));
        m.mesh.colors_rgb.push_back({static_cast<std::uint8_t>(t[k] % 256), 0, 0});
      }
      local[k] = it->second;
    }
    m.mesh.triangles.push_back(local);
  }
  return m;
}

std::multiset<std::array<double, 9>> Soup(const Mesh& m) {
  std::multiset<std::array<double, 9>> out;
  for (const auto& t : m.triangles) {
    int first = 0;
    for (int k = 1; k < 3; ++k) {
      if (m.vertices[t[k]].x() < m.vertices[t[first]].x()) first = k;
    }
    std::array<double, 9> s{};
    for (int k = 0; k < 3; ++k) {
      const auto& v = m.vertices[t[(first + k) % 3]];
      s[3 * k] = v.x();
      s[3 * k + 1] = v.y();
      s[3 * k + 2] = v.z();
    }
    out.insert(s);
  }
  return out;
}

// Publishes a random evolving mesh through a `file://` LCM provider (a real LCM log, no network) and
// rebuilds it with ReplayMeshLog.
void PublishAndReplay(int snapshot_every) {
  const auto log = test::TempDir() / "run.lcmlog";
  LcmOptions options;
  options.enabled = true;
  options.url = "file://" + log.string() + "?mode=w";
  options.snapshot_every = snapshot_every;
  MeshDiffer differ;
  MeshAccumulator truth;
  std::mt19937 rng(3);
  std::set<std::array<VertexId, 3>> live;
  {
    LcmPublisher publisher(options);
    for (int frame = 0; frame < 60; ++frame) {
      for (auto it = live.begin(); it != live.end();) it = (rng() % 7 == 0) ? live.erase(it) : std::next(it);
      for (int a = 0; a < 5; ++a) {
        const VertexId b = 4 * (frame * 5 + a) + 1;
        live.insert({b, b + 1, b + 2 + rng() % 2});
      }
      const auto delta = differ.Update(frame, MakeMesh({live.begin(), live.end()}));
      truth.Apply(delta);
      publisher.PublishMeshDelta(delta);  // never blocks: deltas coalesce while the sender is busy
      publisher.PublishFrameStats(FrameStats{});
    }
    publisher.Flush();
    const auto c = publisher.counters();
    EXPECT_GE(c.mesh_messages, 1);
    EXPECT_LE(c.mesh_messages, 60);
    EXPECT_EQ(c.send_failures, 0);
  }
  const auto replay = ReplayMeshLog(log);
  EXPECT_EQ(replay.sequence_gaps, 0);
  EXPECT_GE(replay.snapshots, 1);
  EXPECT_EQ(replay.last_frame_id, 59);
  EXPECT_GE(replay.other_events, 1);
  EXPECT_EQ(Soup(replay.mesh), Soup(truth.ToMesh()));
  ASSERT_TRUE(replay.mesh.IsConsistent());
}

TEST(LcmPublisher, LogReplayRebuildsThePublishedMesh) { PublishAndReplay(0); }
TEST(LcmPublisher, LogReplayWithPeriodicSnapshots) { PublishAndReplay(4); }

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

TEST(LcmLog, MissingOrForeignFileNamesThePath) {
  EXPECT_THROW(ReplayMeshLog("/no/such.lcmlog"), FileError);
  const auto junk = test::TempDir() / "junk.lcmlog";
  std::ofstream(junk) << "this is not an LCM log";
  try {
    ReplayMeshLog(junk);
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.lcmlog"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("not an LCM log"), std::string::npos);
  }
}

}  // namespace
}  // namespace semap::io
