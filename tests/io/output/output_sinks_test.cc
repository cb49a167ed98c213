#include "io/output/output_sinks.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

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

TEST(MeshFileSink, UnwritableFolderIsAnErrorAtConstructionNamingThePath) {
  // Whatever output.frame_stats says, an unusable folder is reported before the first frame.
  const auto blocker = test::TempDir() / "file";
  std::ofstream(blocker) << "x";
  OutputOptions o;
  o.dir = (blocker / "out").string();
  try {
    MeshFileSink sink(o);
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find((blocker / "out").string()), std::string::npos) << e.what();
  }
}

TEST(MeshFileSink, FolderBecomingUnwritableIsAnErrorNamingThePath) {
  const auto dir = test::TempDir() / "out";
  OutputOptions o;
  o.dir = dir.string();
  MeshFileSink sink(o);
  sink.OnFrame(Stats(0), OneTriangle(1, 10), std::nullopt);
  std::filesystem::remove_all(dir);
  std::ofstream(dir) << "x";
  try {
    sink.OnFinish(Stats(0), {});
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "mesh.ply").string()), std::string::npos) << e.what();
  }
}

TEST(MeshFileSink, AFailedWriteKeepsThePreviousMeshWhole) {
  // A mesh.off that cannot be replaced (here: a folder of that name) is an error; mesh.ply written before it
  // is complete, and no temporary file is left behind.
  const auto dir = test::TempDir() / "out";
  std::filesystem::create_directories(dir / "mesh.off" / "x");
  OutputOptions o;
  o.dir = dir.string();
  MeshFileSink sink(o);
  sink.OnFrame(Stats(0), OneTriangle(1, 10), std::nullopt);
  EXPECT_THROW(sink.OnFinish(Stats(0), {}), FileError);
  EXPECT_EQ(ReadMeshPly(dir / "mesh.ply").num_triangles(), 1u);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "mesh.off" / "x"));
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
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

TEST(StatsFileSink, AFailedStartLeavesThePreviousRunsFilesAlone) {
  const std::filesystem::path dir = test::TempDir() / "stats";
  std::filesystem::create_directories(dir);
  for (const char* name : {"frames.csv", "frames.jsonl", "errors.jsonl", "summary.json"}) {
    std::ofstream(dir / name) << "old " << name << "\n";
  }
  OutputOptions o;
  o.dir = dir.string();
  { StatsFileSink sink(o); }  // constructed, never run (e.g. the LCM URL was refused next)
  for (const char* name : {"frames.csv", "frames.jsonl", "errors.jsonl", "summary.json"}) {
    EXPECT_EQ(test::ReadTextFile(dir / name), std::string("old ") + name + "\n") << name;
  }
  // The first frame starts the new run: the per-frame files are replaced and the old summary goes (a folder
  // without summary.json holds an unfinished run).
  StatsFileSink sink(o);
  sink.OnFrame(Stats(0), {}, std::nullopt);
  EXPECT_EQ(test::ReadTextFile(dir / "frames.csv").find("old"), std::string::npos);
  EXPECT_EQ(test::ReadTextFile(dir / "errors.jsonl"), "");
  EXPECT_FALSE(std::filesystem::exists(dir / "summary.json"));
  sink.OnFinish(Stats(0), {});
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.json"));
}

}  // namespace
}  // namespace semap::io
