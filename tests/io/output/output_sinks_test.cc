#include "io/output/output_sinks.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

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

// A CSV row's cells by the header's names (no quoting: frames.csv has none); an empty map when the row has
// another number of cells than the header.
std::map<std::string, std::string> CsvRow(const std::string& header, const std::string& row) {
  const std::vector<std::string> names = test::CsvCells(header), cells = test::CsvCells(row);
  std::map<std::string, std::string> out;
  if (names.size() != cells.size()) return out;
  for (std::size_t i = 0; i < names.size(); ++i) out[names[i]] = cells[i];
  return out;
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

// A dropped frame is a line of errors.jsonl with its reason; each frame's row has its latency per step and
// the drops so far by reason; summary.json has the run's latency per step and the frames integrated.
TEST(StatsFileSink, DropsLatencyAndTheirSummary) {
  OutputOptions o;
  o.dir = (test::TempDir() / "latency").string();
  auto frame = [](std::int64_t id, double published_ms, std::int64_t behind) {
    FrameStats s = Stats(id);
    s.latency = {5.0, 40.0, 30.0, 90.0, published_ms};
    s.dropped_by_reason = {{"behind", behind}, {"no_keyframe_labels", 0}};
    s.frames_dropped = behind;
    s.latencies = {{"depth", 40.0, 40.0, 40.0, 40.0, 40.0, 0},
                   {"published", published_ms, 110.0, 100.0, 120.0, 120.0, 0}};
    return s;
  };
  {
    StatsFileSink sink(o);
    sink.OnFrame(frame(0, 100.0, 0), {}, std::nullopt);
    sink.OnFrameDropped(1, 0.1, "behind");
    sink.OnFrame(frame(2, 120.0, 1), {}, std::nullopt);
    sink.OnFinish(frame(2, 120.0, 1), {});
  }
  const std::filesystem::path dir(o.dir);
  std::ifstream csv(dir / "frames.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u);  // the header and the two frames integrated
  std::map<std::string, std::string> cell = CsvRow(lines[0], lines[2]);
  EXPECT_EQ(cell["latency_depth_ms"], "40");
  EXPECT_EQ(cell["latency_labels_ms"], "30");
  EXPECT_EQ(cell["latency_map_ms"], "90");
  EXPECT_EQ(cell["latency_published_ms"], "120");
  EXPECT_EQ(cell["late_ms"], "5");
  EXPECT_EQ(cell["dropped_behind"], "1");
  EXPECT_EQ(cell["dropped_no_keyframe_labels"], "0");
  std::ifstream errors(dir / "errors.jsonl");
  std::string line;
  std::getline(errors, line);
  const auto drop = nlohmann::json::parse(line);
  EXPECT_EQ(drop["frame_id"], 1);
  EXPECT_EQ(drop["dropped"], "behind");
  EXPECT_DOUBLE_EQ(drop["timestamp_s"].get<double>(), 0.1);
  const auto j = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_EQ(j["frames_integrated"], 3);
  EXPECT_EQ(j["frames_dropped"], 1);
  EXPECT_EQ(j["dropped_by_reason"]["behind"], 1);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["published"]["p50"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["published"]["p95"].get<double>(), 120.0);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["published"]["max"].get<double>(), 120.0);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["depth"]["p95"].get<double>(), 40.0);
}

// Figures measured outside the stages (visual odometry's) become columns named by the first frame's, and keys
// of the JSON lines; a frame without them leaves its cells empty.
TEST(StatsFileSink, FiguresOfAFigureSourceAreColumns) {
  OutputOptions o;
  o.dir = (test::TempDir() / "figures").string();
  {
    StatsFileSink sink(o);
    sink.SetFigureSource([](std::int64_t id) {
      if (id == 1) return std::vector<FrameFigure>{};
      return std::vector<FrameFigure>{{"odometry_features", 100.0 + id}, {"odometry_inliers", 50.0}};
    });
    for (int id : {0, 1, 2}) sink.OnFrame(Stats(id), {}, std::nullopt);
    sink.OnFinish(Stats(2), {});
  }
  const std::filesystem::path dir(o.dir);
  std::ifstream csv(dir / "frames.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find(",cpu_s,odometry_features,odometry_inliers"), std::string::npos) << header;
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(CsvRow(header, rows[0])["odometry_features"], "100");
  EXPECT_EQ(CsvRow(header, rows[0])["odometry_inliers"], "50");
  EXPECT_EQ(CsvRow(header, rows[1])["odometry_features"], "");
  EXPECT_EQ(CsvRow(header, rows[1])["odometry_inliers"], "");
  EXPECT_EQ(CsvRow(header, rows[2])["odometry_features"], "102");
  std::ifstream jsonl(dir / "frames.jsonl");
  std::getline(jsonl, line);
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(line)["odometry_features"].get<double>(), 100.0);
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

// A drive's mesh stream: a live mesh that moves along a strip of vertices, and behind it triangles the map
// finalises (some published while live, some never), with vertex colours that change from frame to frame (a
// vertex's last upsert wins), made into deltas by the MeshDiffer as the pipeline does.
std::vector<MeshDelta> DriveDeltas(int frames, std::uint32_t seed) {
  std::mt19937 rng(seed);
  MeshDiffer differ;
  std::vector<MeshDelta> deltas;
  auto mesh_of = [&](const std::vector<std::array<VertexId, 3>>& tris, int frame) {
    IdentifiedMesh m;
    std::map<VertexId, std::uint32_t> index;
    for (const auto& t : tris) {
      std::array<std::uint32_t, 3> local{};
      for (int k = 0; k < 3; ++k) {
        const auto [it, inserted] = index.emplace(t[k], std::uint32_t(m.vertex_ids.size()));
        if (inserted) {
          m.vertex_ids.push_back(t[k]);
          m.mesh.vertices.emplace_back(double(t[k]), double(t[k] % 7), 0.5 * double(t[k] % 3));
          m.mesh.colors_rgb.push_back({std::uint8_t(frame), std::uint8_t(t[k]), std::uint8_t(frame + t[k])});
          m.mesh.labels.push_back(Label(t[k] % 19));
        }
        local[k] = it->second;
      }
      m.mesh.triangles.push_back(local);
    }
    return m;
  };
  std::vector<std::array<VertexId, 3>> previous_live;
  for (int frame = 0; frame < frames; ++frame) {
    const VertexId start = VertexId(6 * frame);
    std::vector<std::array<VertexId, 3>> live, frozen;
    for (VertexId v = start; v < start + 40; ++v) {
      if (rng() % 4 != 0) live.push_back({v, v + 1, v + 2});
    }
    // Behind the live strip: some of the last frame's live triangles, and some never published.
    for (const auto& t : previous_live) {
      if (t[0] < start && rng() % 4 != 0) frozen.push_back(t);
    }
    if (frame % 3 == 0 && start >= 4) frozen.push_back({start - 4, start - 2, start - 3});
    deltas.push_back(differ.Update(frame, mesh_of(live, frame), mesh_of(frozen, frame)));
    previous_live = live;
  }
  return deltas;
}

void ExpectSameMesh(const Mesh& got, const Mesh& expected) {
  EXPECT_EQ(got.vertices, expected.vertices);
  EXPECT_EQ(got.triangles, expected.triangles);
  EXPECT_EQ(got.colors_rgb, expected.colors_rgb);
  EXPECT_EQ(got.labels, expected.labels);
}

TEST(MeshFileSink, KeepsOnlyTheLiveMeshInMemoryAndWritesWhatTheAccumulatorWould) {
  const auto deltas = DriveDeltas(300, 5);
  const auto dir = test::TempDir() / "out";
  OutputOptions o;
  o.dir = dir.string();
  MeshFileSink sink(o);
  MeshAccumulator reference;  // everything in memory: what the sink wrote before it spilled
  std::size_t most_in_memory = 0;
  for (std::size_t i = 0; i + 1 < deltas.size(); ++i) {
    sink.OnFrame(Stats(std::int64_t(i)), deltas[i], std::nullopt);
    reference.Apply(deltas[i]);
    most_in_memory = std::max(most_in_memory, sink.num_triangles_in_memory());
  }
  EXPECT_TRUE(std::filesystem::exists(dir / MeshFileSink::kSpillFileName));
  EXPECT_GT(sink.num_triangles_spilled(), 500u);
  EXPECT_LE(most_in_memory, 120u);  // the live strip and what finalisation has not taken yet
  sink.OnFinish(Stats(299), deltas.back());
  reference.Apply(deltas.back());
  EXPECT_FALSE(std::filesystem::exists(dir / MeshFileSink::kSpillFileName));
  const Mesh expected = reference.ToMesh();
  ASSERT_GT(expected.num_triangles(), sink.num_triangles_spilled());
  ExpectSameMesh(sink.mesh(), expected);
  // The files hold that mesh, byte for byte.
  WriteMeshPly(dir / "expected.ply", expected, PlyEncoding::kBinaryLittleEndian);
  WriteMeshOff(dir / "expected.off", expected);
  EXPECT_EQ(test::ReadFile(dir / "mesh.ply"), test::ReadFile(dir / "expected.ply"));
  EXPECT_EQ(test::ReadFile(dir / "mesh.off"), test::ReadFile(dir / "expected.off"));
}

TEST(MeshFileSink, ASpillFileThatCannotBeWrittenLosesNothing) {
  // The folder is gone when the first finalised triangles come: they stay in memory, and so do all later
  // ones; once the folder is back, the mesh written at the end is whole.
  const auto deltas = DriveDeltas(60, 9);
  const auto dir = test::TempDir() / "out";
  OutputOptions o;
  o.dir = dir.string();
  MeshFileSink sink(o);
  MeshAccumulator reference;
  std::filesystem::remove_all(dir);
  for (std::size_t i = 0; i + 1 < deltas.size(); ++i) {
    sink.OnFrame(Stats(std::int64_t(i)), deltas[i], std::nullopt);
    reference.Apply(deltas[i]);
  }
  EXPECT_NE(sink.spill_error().find(MeshFileSink::kSpillFileName), std::string::npos) << sink.spill_error();
  EXPECT_EQ(sink.num_triangles_spilled(), 0u);
  std::filesystem::create_directories(dir);
  sink.OnFinish(Stats(59), deltas.back());
  reference.Apply(deltas.back());
  const Mesh expected = reference.ToMesh();
  ExpectSameMesh(sink.mesh(), expected);
  EXPECT_EQ(ReadMeshPly(dir / "mesh.ply").num_triangles(), expected.num_triangles());
}

}  // namespace
}  // namespace semap::io
