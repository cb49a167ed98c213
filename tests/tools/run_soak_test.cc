// Soak (label soak, not in the default suite; scripts/soak runs it and plots the curve): a generated
// sequence, looped (input.loops, each pass shifted onto new ground) to SEMAP_SOAK_FRAMES frames (default
// 10,000), streamed through the whole engine by `semap run` with LCM publishing on. Every 100 frames the RSS,
// map size, per-frame time and queue occupancy go to soak.csv (in SEMAP_SOAK_DIR, default a temporary
// folder).
//
// Pass conditions:
//  - no crash, no deadlock: the run ends by itself (bounded by `timeout`) with exit code 0;
//  - every frame accounted for: processed + failed + dropped = frames of the looped sequence, and on this
//    intact sequence none failed or was dropped;
//  - the written mesh is a 2-manifold with boundary (the independent checker on mesh.ply);
//  - the map's memory bound holds: its live Delaunay size (vertices, cells) after warm-up stays within 1.5×
//  of
//    its size at the end of warm-up (the finalised parts leave it);
//  - RSS after warm-up grows by at most 64 MiB + 192 B per published mesh triangle added since. What grows by
//    design is the LCM sender's finalised blocks, kept encoded for its round-robin (late subscribers, lost
//    datagrams): ~143 B per triangle on a 4,000-frame soak (RSS 96.1 -> 106.8 MB over 74 k triangles), while
//    the same run without LCM stays flat (94.8 -> 96.1 MB): the mesh kept for mesh.ply is the live one
//    (MeshFileSink moves the finalised triangles to a spill file as they come). Nothing else may grow; 64 MiB
//    covers allocator slack;
//  - per-frame time does not grow: the median CPU time per frame (the process's, all threads) over the last
//    quarter of the run is at most 1.5× the median over the quarter after warm-up (a cost that grows with the
//    drive would multiply it over 10,000 frames). CPU time, not wall time, so that other processes sharing
//    the cores do not decide the verdict; the wall time per frame is recorded next to it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/engine/map/manifold_checker.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;

constexpr int kSequenceFrames = 200;  // generated once, looped
constexpr int kEvery = 100;           // a soak.csv row every kEvery frames
// Small images, 200 map points per frame and a live map of 10 frames (finalised after that): about 10
// frames/s on 2 cores, so 10,000 frames take ~17 min. The soak is about length (memory, time, accounting),
// not load: per-frame load is measured by scripts/bench.
const std::string kSynth =
    " --set synth.image_width_px=416 --set synth.image_height_px=128 --set synth.cx_px=208 --set "
    "synth.cy_px=64"
    " --set synth.lidar_azimuth_steps=256";
const std::string kRun =
    " --set depth.max_points_per_frame=200 --set map.finalise_age_frames=10 --set map.finalise_every_frames=5"
    " --progress-interval 30";

int EnvInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}

// frames.csv as columns by name.
struct Csv {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  int Col(const std::string& name) const {
    const auto it = std::find(names.begin(), names.end(), name);
    EXPECT_NE(it, names.end()) << "no column " << name;
    return static_cast<int>(it - names.begin());
  }
};

Csv ReadCsv(const fs::path& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return csv;
  std::istringstream header(line);
  for (std::string f; std::getline(header, f, ',');) csv.names.push_back(f);
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::vector<double> values;
    for (std::string f; std::getline(row, f, ',');) values.push_back(std::stod(f));
    if (values.size() == csv.names.size()) csv.rows.push_back(std::move(values));
  }
  return csv;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The soak curve, a row every kEvery frames, written to `path`: the frames' rows (indices into csv.rows)
// and the mean CPU ms per frame since the previous row.
struct Curve {
  std::vector<int> at;
  std::vector<double> frame_cpu_ms;
};

Curve WriteCurve(const Csv& csv, const fs::path& path) {
  const int c_elapsed = csv.Col("elapsed_s"), c_cpu = csv.Col("cpu_s"), c_rss = csv.Col("rss_mb"),
            c_vertices = csv.Col("map_vertices"), c_cells = csv.Col("map_cells"),
            c_tris = csv.Col("mesh_triangles"), c_map_ms = csv.Col("map_ms"),
            c_depth_q = csv.Col("depth_queue"), c_simplify_q = csv.Col("simplify_queue"),
            c_map_q = csv.Col("map_queue");
  // Per-frame times (wall and CPU) are means since the previous row.
  std::ofstream curve(path);
  curve << "frame,rss_mb,map_vertices,map_cells,mesh_triangles,frame_ms,map_ms,depth_queue,simplify_queue,"
           "map_queue,frame_cpu_ms\n";
  Curve out;
  for (size_t i = kEvery; i <= csv.rows.size(); i += kEvery) {
    const auto& r = csv.rows[i - 1];
    const auto& prev = csv.rows[i - kEvery];
    const double ms = 1000.0 * (r[c_elapsed] - prev[c_elapsed]) / (kEvery - 1);
    const double cpu_ms = 1000.0 * (r[c_cpu] - prev[c_cpu]) / (kEvery - 1);
    double map_ms = 0.0;
    for (size_t j = i - kEvery; j < i; ++j) map_ms += csv.rows[j][c_map_ms] / kEvery;
    curve << i << ',' << r[c_rss] << ',' << r[c_vertices] << ',' << r[c_cells] << ',' << r[c_tris] << ','
          << ms << ',' << map_ms << ',' << r[c_depth_q] << ',' << r[c_simplify_q] << ',' << r[c_map_q] << ','
          << cpu_ms << '\n';
    out.at.push_back(static_cast<int>(i - 1));
    out.frame_cpu_ms.push_back(cpu_ms);
  }
  return out;
}

// The live map's size swings within a pass of the looped sequence (2-5x on this small map, with far points
// waiting for confirmation and finalisation every few frames), so one row is no reference for its bound:
// the largest size over the second half of the curve's rows after warm-up is held against the largest over
// the first half (the same number of rows each, many passes of the sequence), which a growing map exceeds.
// RSS is held against its value at the end of warm-up (the row `warm` − 1) plus the allowance the file's
// comment explains.
struct MemoryFigures {
  double first_vertices = 0, first_cells = 0, second_vertices = 0, second_cells = 0, max_rss = 0;
};

MemoryFigures ExpectBoundedMemory(const Csv& csv, const Curve& curve, size_t warm) {
  const int c_rss = csv.Col("rss_mb"), c_vertices = csv.Col("map_vertices"), c_cells = csv.Col("map_cells"),
            c_tris = csv.Col("mesh_triangles");
  const auto& w = csv.rows[curve.at[warm - 1]];
  const size_t half = warm + (curve.at.size() - warm) / 2;
  MemoryFigures m;
  for (size_t k = warm; k < curve.at.size(); ++k) {
    const auto& r = csv.rows[curve.at[k]];
    double& vertices = k < half ? m.first_vertices : m.second_vertices;
    double& cells = k < half ? m.first_cells : m.second_cells;
    vertices = std::max(vertices, r[c_vertices]);
    cells = std::max(cells, r[c_cells]);
    const double allowed_mb = w[c_rss] + 64.0 + 192.0 * (r[c_tris] - w[c_tris]) / (1024.0 * 1024.0);
    EXPECT_LE(r[c_rss], allowed_mb) << "RSS at frame " << curve.at[k] << " (" << r[c_tris]
                                    << " mesh triangles)";
    m.max_rss = std::max(m.max_rss, r[c_rss]);
  }
  EXPECT_LE(m.second_vertices, 1.5 * m.first_vertices) << "the map's live size grows: memory bound broken";
  EXPECT_LE(m.second_cells, 1.5 * m.first_cells) << "the map's live size grows: memory bound broken";
  return m;
}

TEST(Soak, TenThousandFramesThroughTheWholeEngine) {
  const int total = EnvInt("SEMAP_SOAK_FRAMES", 10000);
  const int loops = (total + kSequenceFrames - 1) / kSequenceFrames;
  const int frames = loops * kSequenceFrames;
  const char* env_dir = std::getenv("SEMAP_SOAK_DIR");
  const fs::path dir = env_dir && *env_dir ? fs::path(env_dir) : test::TempDir();
  fs::create_directories(dir);
  const fs::path seq = dir / "seq", out = dir / "run";
  fs::remove_all(seq);
  fs::remove_all(out);

  const auto synth = test::RunSemap("synth --preset urban --frames " + std::to_string(kSequenceFrames) +
                                    " --seed 11 --out " + seq.string() + kSynth);
  ASSERT_EQ(synth.exit_code, 0) << synth.output;

  // 3 h is far beyond the expected ~17 min: reaching it means a deadlock.
  const auto run = test::RunShell("timeout 10800 " + std::string(SEMAP_EXE) + " run " + seq.string() +
                                  " --out " + out.string() + " --set input.loops=" + std::to_string(loops) +
                                  " --lcm-url 'udpm://239.255.76.70:7691?ttl=0'" + kRun + " > " +
                                  (dir / "run.log").string());
  const std::string log = test::ReadFile(dir / "run.log");
  const std::string log_tail = log.substr(log.size() > 4000 ? log.size() - 4000 : 0);
  ASSERT_NE(run.exit_code, 124) << "deadlock: the run did not end in 3 h\n" << log_tail;
  ASSERT_EQ(run.exit_code, 0) << log_tail;

  // Every frame accounted for.
  std::ifstream summary_in(out / "summary.json");
  const auto summary = nlohmann::json::parse(summary_in);
  const std::int64_t processed = summary["frames_processed"], failed = summary["frames_failed"],
                     dropped = summary["frames_dropped"];
  EXPECT_EQ(processed + failed + dropped, frames) << summary.dump();
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(dropped, 0);
  EXPECT_NE(log.find("LCM: "), std::string::npos) << log_tail;

  const Csv csv = ReadCsv(out / "frames.csv");
  ASSERT_EQ(static_cast<std::int64_t>(csv.rows.size()), processed);
  const Curve curve = WriteCurve(csv, dir / "soak.csv");
  ASSERT_GE(curve.at.size(), 8u) << "too short a run to judge";

  // Warm-up: the first 10 % of the frames (at least one pass of the sequence).
  const size_t warm = std::max<size_t>(curve.at.size() / 10, kSequenceFrames / kEvery);
  const MemoryFigures memory = ExpectBoundedMemory(csv, curve, warm);

  const std::vector<double>& frame_cpu_ms = curve.frame_cpu_ms;
  const size_t q = (curve.at.size() - warm) / 4;
  const double early =
      Median({frame_cpu_ms.begin() + warm, frame_cpu_ms.begin() + warm + std::max<size_t>(q, 1)});
  const double late = Median({frame_cpu_ms.end() - std::max<size_t>(q, 1), frame_cpu_ms.end()});
  EXPECT_LE(late, 1.5 * early) << "CPU time per frame grows: " << early << " ms after warm-up, " << late
                               << " ms at the end";

  // The mesh of a run that finalised all the time: one manifold across every seam.
  const test::ManifoldReport manifold =
      test::CheckManifold(io::ReadMeshPly(out / "mesh.ply"), /*allow_boundary=*/true);
  EXPECT_TRUE(manifold.ok()) << manifold.num_nonmanifold_edges << " non-manifold edges, "
                             << manifold.num_nonmanifold_vertices << " non-manifold vertices\n"
                             << manifold.Summary();

  const int c_rss = csv.Col("rss_mb"), c_tris = csv.Col("mesh_triangles");
  std::ofstream(dir / "soak_summary.json")
      << nlohmann::json{{"frames", frames},
                        {"processed", processed},
                        {"failed", failed},
                        {"dropped", dropped},
                        {"fps", summary["fps"]},
                        {"elapsed_s", summary["elapsed_s"]},
                        {"warmup_frames", curve.at[warm - 1] + 1},
                        {"rss_mb_after_warmup", csv.rows[curve.at[warm - 1]][c_rss]},
                        {"rss_mb_max_after_warmup", memory.max_rss},
                        {"rss_mb_end", csv.rows.back()[c_rss]},
                        {"map_vertices_max_first_half", memory.first_vertices},
                        {"map_vertices_max_second_half", memory.second_vertices},
                        {"map_cells_max_first_half", memory.first_cells},
                        {"map_cells_max_second_half", memory.second_cells},
                        {"mesh_triangles_end", csv.rows.back()[c_tris]},
                        {"frame_cpu_ms_median_early", early},
                        {"frame_cpu_ms_median_late", late}}
             .dump(2)
      << '\n';
}

}  // namespace
}  // namespace semap::tools
