#include "io/output/output_sinks.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

MeshDelta OneTriangle(TriangleId id, VertexId base) {
  MeshDelta d;
  d.vertex_ids = {base, base + 1, base + 2};
  d.vertex_positions = {{double(base), 0, 0}, {double(base) + 1, 0, 0}, {double(base), 1, 0}};
  d.vertex_labels = {1, 1, 3};
  d.vertex_colors_rgb = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}};
  d.added_triangle_ids = {id};
  d.added_triangles = {{base, base + 1, base + 2}};
  return d;
}

FrameStats Stats(std::int64_t frame) {
  FrameStats s;
  s.frame_id = frame;
  s.frames_processed = frame + 1;
  s.stages = {{"read", 1.0}, {"depth", 20.0}};
  return s;
}

TEST(MeshFileSink, WritesTheAccumulatedMeshAsPlyAndOff) {
  OutputOptions o;
  o.dir = (test::TempDir() / "out").string();
  MeshFileSink sink(o);
  sink.OnFrame(Stats(0), OneTriangle(1, 10), std::nullopt);
  MeshDelta second = OneTriangle(2, 20);
  second.removed_triangle_ids = {1};
  sink.OnFrame(Stats(1), second, std::nullopt);
  sink.OnFinish(Stats(1), OneTriangle(3, 30));
  ASSERT_EQ(sink.written().size(), 2u);
  const Mesh ply = ReadMeshPly(std::filesystem::path(o.dir) / "mesh.ply");
  EXPECT_EQ(ply.num_triangles(), 2u);
  EXPECT_EQ(ply.num_vertices(), 6u);
  ASSERT_EQ(ply.labels.size(), 6u);
  const Mesh off = ReadMeshOff(std::filesystem::path(o.dir) / "mesh.off");
  EXPECT_EQ(off.num_triangles(), 2u);
  EXPECT_EQ(std::filesystem::file_size(std::filesystem::path(o.dir) / "mesh.off"), OffSizeBytes(off));
}

TEST(MeshFileSink, UnwritableFolderIsAnErrorNamingThePath) {
  const auto blocker = test::TempDir() / "file";
  std::ofstream(blocker) << "x";
  OutputOptions o;
  o.dir = (blocker / "out").string();
  MeshFileSink sink(o);
  sink.OnFrame(Stats(0), OneTriangle(1, 10), std::nullopt);
  try {
    sink.OnFinish(Stats(0), {});
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find((blocker / "out").string()), std::string::npos) << e.what();
  }
}

TEST(StatsFileSink, WritesCsvJsonLinesErrorsAndSummary) {
  OutputOptions o;
  o.dir = (test::TempDir() / "stats").string();
  {
    StatsFileSink sink(o);
    sink.OnFrame(Stats(0), {}, std::nullopt);
    sink.OnFrameError(1, "depth", "no valid disparity");
    sink.OnFrame(Stats(2), {}, std::nullopt);
    auto final_stats = Stats(2);
    final_stats.fps = 12.5;
    sink.OnFinish(final_stats, {});
  }
  const std::filesystem::path dir(o.dir);
  std::ifstream csv(dir / "frames.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("depth_ms"), std::string::npos);
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 2);
  std::ifstream errors(dir / "errors.jsonl");
  std::getline(errors, line);
  EXPECT_EQ(nlohmann::json::parse(line)["frame_id"], 1);
  std::ifstream summary(dir / "summary.json");
  const auto j = nlohmann::json::parse(summary);
  EXPECT_DOUBLE_EQ(j["fps"].get<double>(), 12.5);
  EXPECT_DOUBLE_EQ(j["stages"]["depth"]["last_ms"].get<double>(), 20.0);
}

TEST(StatsFileSink, UnwritableFolderFailsAtConstructionNamingThePath) {
  const auto blocker = test::TempDir() / "file";
  std::ofstream(blocker) << "x";
  OutputOptions o;
  o.dir = (blocker / "stats").string();
  EXPECT_THROW(StatsFileSink{o}, FileError);
}

}  // namespace
}  // namespace semap::io
