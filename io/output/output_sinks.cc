#include "io/output/output_sinks.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "io/atomic_file.h"
#include "io/mesh/ply_off.h"

namespace semap::io {
namespace {

std::ofstream OpenForWriting(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  if (!out) throw FileError(path, "cannot open for writing");
  return out;
}

nlohmann::json StatsJson(const FrameStats& s) {
  nlohmann::json j;
  j["frame_id"] = s.frame_id;
  j["timestamp_s"] = s.timestamp_s;
  j["elapsed_s"] = s.elapsed_s;
  j["fps"] = s.fps;
  j["frames_processed"] = s.frames_processed;
  j["frames_dropped"] = s.frames_dropped;
  j["frames_failed"] = s.frames_failed;
  for (const auto& st : s.stages) {
    j["stages"][st.name] = {{"last_ms", st.last_ms}, {"mean_ms", st.mean_ms}, {"p50_ms", st.p50_ms},
                            {"p95_ms", st.p95_ms},   {"max_ms", st.max_ms},   {"queue", st.queue_occupancy}};
  }
  j["points_in"] = s.points_in;
  j["points_kept"] = s.points_kept;
  for (const auto& c : s.class_counts)
    j["classes"][std::to_string(c.label)] = {{"in", c.in}, {"kept", c.kept}};
  j["map_vertices"] = s.map_vertices;
  j["map_cells"] = s.map_cells;
  j["map_rays"] = s.map_rays;
  j["mesh_triangles"] = s.mesh_triangles;
  j["rss_mb"] = s.rss_mb;
  j["cpu_s"] = s.cpu_s;
  j["latency_ms"] = {{"late", s.latency.late_ms},
                     {"depth", s.latency.depth_ms},
                     {"labels", s.latency.labels_ms},
                     {"map", s.latency.map_ms},
                     {"published", s.latency.published_ms}};
  for (const auto& [reason, count] : s.dropped_by_reason) j["dropped_by_reason"][reason] = count;
  return j;
}

// The run's latency per step over its frames: p50, p95 (over the last frames, TimingStats' window), max.
nlohmann::json LatencySummaryJson(const FrameStats& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& l : s.latencies) {
    j[l.name] = {{"mean", l.mean_ms}, {"p50", l.p50_ms}, {"p95", l.p95_ms}, {"max", l.max_ms}};
  }
  return j;
}

}  // namespace

MeshFileSink::MeshFileSink(const OutputOptions& options)
    : options_(options), spill_(std::filesystem::path(options.dir) / kSpillFileName) {
  options_.Check();
  CheckWritableFolder(options_.dir);
}

void MeshFileSink::OnFrame(const FrameStats&, const MeshDelta& delta, const std::optional<Pose3d>&) {
  accumulator_.Apply(delta);
  if (delta.finalised_triangle_ids.empty()) return;
  if (!spill_error_.empty()) return;  // kept in memory since the spill file failed
  const MeshDelta finalised = accumulator_.TakeTriangles(delta.finalised_triangle_ids);
  try {
    spill_.Append(finalised);
  } catch (const FileError& e) {
    accumulator_.Apply(finalised);  // back where they were: nothing is lost
    spill_error_ = e.what();
  }
}

Mesh MeshFileSink::AssembleMesh() {
  // Every triangle with its id, and every vertex record in the order it came (spilled ones first, then the
  // live mesh's: the latest): a vertex takes its last record, as MeshAccumulator's upserts do. Flat arrays
  // sorted once, not hash maps and their ordered copies as ToMesh makes: the end of a 2,000-frame drive
  // (2.1 M triangles) peaked at 537 MiB instead of 710 MiB (bench/results/long-drives.md, "The finalised
  // mesh leaves memory as it comes").
  struct VertexRecord {
    VertexId id;
    std::uint64_t order;
    Eigen::Vector3d position;
    std::array<std::uint8_t, 3> color_rgb;
    Label label;
  };
  std::vector<std::pair<TriangleId, std::array<VertexId, 3>>> triangles;
  std::vector<VertexRecord> records;
  triangles.reserve(spill_.num_triangles() + accumulator_.num_triangles());
  const auto take = [&](const MeshDelta& d) {
    for (std::size_t i = 0; i < d.added_triangle_ids.size(); ++i) {
      triangles.emplace_back(d.added_triangle_ids[i], d.added_triangles[i]);
    }
    for (std::size_t i = 0; i < d.vertex_ids.size(); ++i) {
      records.push_back(
          {d.vertex_ids[i], records.size(), d.vertex_positions[i],
           d.vertex_colors_rgb.empty() ? std::array<std::uint8_t, 3>{0, 0, 0} : d.vertex_colors_rgb[i],
           d.vertex_labels.empty() ? Label(0) : d.vertex_labels[i]});
    }
  };
  spill_.ForEach(take);
  take(accumulator_.AsSnapshot(-1));
  std::sort(triangles.begin(), triangles.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::sort(records.begin(), records.end(), [](const VertexRecord& a, const VertexRecord& b) {
    return a.id != b.id ? a.id < b.id : a.order > b.order;  // the latest record of each vertex first
  });
  records.erase(std::unique(records.begin(), records.end(),
                            [](const VertexRecord& a, const VertexRecord& b) { return a.id == b.id; }),
                records.end());
  const auto index_of = [&](VertexId id) {
    const auto it = std::lower_bound(records.begin(), records.end(), id,
                                     [](const VertexRecord& r, VertexId v) { return r.id < v; });
    SEMAP_ASSERT(it != records.end() && it->id == id, "triangle references unknown vertex " << id);
    return std::uint32_t(it - records.begin());
  };
  Mesh mesh;
  mesh.vertices.reserve(records.size());
  for (const VertexRecord& r : records) mesh.vertices.push_back(r.position);
  if (accumulator_.has_colors()) {
    for (const VertexRecord& r : records) mesh.colors_rgb.push_back(r.color_rgb);
  }
  if (accumulator_.has_labels()) {
    for (const VertexRecord& r : records) mesh.labels.push_back(r.label);
  }
  mesh.triangles.reserve(triangles.size());
  for (const auto& [id, t] : triangles)
    mesh.triangles.push_back({index_of(t[0]), index_of(t[1]), index_of(t[2])});
  return mesh;
}

void MeshFileSink::OnFinish(const FrameStats&, const MeshDelta& final_delta) {
  accumulator_.Apply(final_delta);
  mesh_ = AssembleMesh();
  spill_.Remove();
  const Mesh& mesh = mesh_;
  const std::filesystem::path dir(options_.dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (options_.mesh_ply) {
    WriteMeshPly(dir / "mesh.ply", mesh,
                 options_.ply_ascii ? PlyEncoding::kAscii : PlyEncoding::kBinaryLittleEndian);
    written_.push_back(dir / "mesh.ply");
  }
  if (options_.mesh_off) {
    WriteMeshOff(dir / "mesh.off", mesh);
    written_.push_back(dir / "mesh.off");
  }
}

StatsFileSink::StatsFileSink(const OutputOptions& options) : dir_(options.dir) {
  options.Check();
  CheckWritableFolder(dir_);
}

void StatsFileSink::OpenOnce() {
  if (opened_) return;
  opened_ = true;
  // The previous run's summary goes first: a folder without summary.json holds an unfinished run.
  std::error_code ec;
  std::filesystem::remove(dir_ / "summary.json", ec);
  csv_ = OpenForWriting(dir_ / "frames.csv");
  jsonl_ = OpenForWriting(dir_ / "frames.jsonl");
  errors_ = OpenForWriting(dir_ / "errors.jsonl");
}

void StatsFileSink::OnFrame(const FrameStats& s, const MeshDelta&, const std::optional<Pose3d>&) {
  OpenOnce();
  const std::vector<FrameFigure> figures =
      figure_source_ ? figure_source_(s.frame_id) : std::vector<FrameFigure>();
  if (!header_written_) {
    csv_ << "frame_id,timestamp_s,elapsed_s,fps,frames_processed,frames_dropped,frames_failed";
    // A step of a stage ("map.votes") has a time and no queue of its own.
    for (const auto& st : s.stages) {
      csv_ << "," << st.name << "_ms";
      if (!IsStageStep(st.name)) csv_ << "," << st.name << "_queue";
    }
    csv_ << ",points_in,points_kept,map_vertices,map_cells,map_rays,mesh_triangles,rss_mb,cpu_s";
    // The figures measured outside the stages (e.g. visual odometry's): the first frame's names are the
    // columns.
    for (const auto& f : figures) {
      csv_ << "," << f.name;
      figure_columns_.push_back(f.name);
    }
    // The frame's latency from its sensor time per step, how late it entered, and the frames dropped so far
    // by reason (each dropped frame is a line of errors.jsonl).
    for (const char* step : kLatencyStepNames) csv_ << ",latency_" << step << "_ms";
    csv_ << ",late_ms";
    for (const auto& [reason, count] : s.dropped_by_reason) {
      csv_ << ",dropped_" << reason;
      drop_columns_.push_back(reason);
    }
    csv_ << '\n';
    header_written_ = true;
  }
  csv_ << s.frame_id << ',' << s.timestamp_s << ',' << s.elapsed_s << ',' << s.fps << ','
       << s.frames_processed << ',' << s.frames_dropped << ',' << s.frames_failed;
  for (const auto& st : s.stages) {
    csv_ << ',' << st.last_ms;
    if (!IsStageStep(st.name)) csv_ << ',' << st.queue_occupancy;
  }
  csv_ << ',' << s.points_in << ',' << s.points_kept << ',' << s.map_vertices << ',' << s.map_cells << ','
       << s.map_rays << ',' << s.mesh_triangles << ',' << s.rss_mb << ',' << s.cpu_s;
  for (const auto& name : figure_columns_) {
    csv_ << ',';
    const auto it =
        std::find_if(figures.begin(), figures.end(), [&](const FrameFigure& f) { return f.name == name; });
    if (it != figures.end()) csv_ << it->value;  // empty when this frame lacks it
  }
  const FrameLatency& l = s.latency;
  csv_ << ',' << l.depth_ms << ',' << l.labels_ms << ',' << l.map_ms << ',' << l.published_ms << ','
       << l.late_ms;
  for (const auto& reason : drop_columns_) {
    const auto it = std::find_if(s.dropped_by_reason.begin(), s.dropped_by_reason.end(),
                                 [&](const auto& d) { return d.first == reason; });
    csv_ << ',' << (it != s.dropped_by_reason.end() ? it->second : 0);
  }
  csv_ << '\n';
  nlohmann::json line = StatsJson(s);
  for (const auto& f : figures) line[f.name] = f.value;
  jsonl_ << line.dump() << '\n';
  // Flushed per frame (a few hundred bytes at a few frames per second): the files can be followed live, hold
  // every frame processed when the process dies, and a failing disk is reported at the frame it fails.
  csv_.flush();
  jsonl_.flush();
  if (!csv_) throw FileError(dir_ / "frames.csv", "write failed");
  if (!jsonl_) throw FileError(dir_ / "frames.jsonl", "write failed");
}

void StatsFileSink::OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) {
  OpenOnce();
  errors_ << nlohmann::json{{"frame_id", frame_id}, {"stage", stage}, {"error", what}}.dump() << '\n';
  errors_.flush();
  if (!errors_) throw FileError(dir_ / "errors.jsonl", "write failed");
}

void StatsFileSink::OnFrameDropped(std::int64_t frame_id, double timestamp_s, const std::string& reason) {
  OpenOnce();
  errors_ << nlohmann::json{{"frame_id", frame_id}, {"timestamp_s", timestamp_s}, {"dropped", reason}}.dump()
          << '\n';
  errors_.flush();
  if (!errors_) throw FileError(dir_ / "errors.jsonl", "write failed");
}

void StatsFileSink::OnFinish(const FrameStats& stats, const MeshDelta&) {
  OpenOnce();
  csv_.flush();
  jsonl_.flush();
  errors_.flush();
  WriteFileAtomically(dir_ / "summary.json", SummaryJson(stats) + "\n");
}

std::string SummaryJson(const FrameStats& stats) {
  nlohmann::json j = StatsJson(stats);
  j.erase("latency_ms");  // the last frame's: the run's figures follow
  j["latency_ms"] = LatencySummaryJson(stats);
  j["frames_integrated"] = stats.frames_processed;
  return j.dump(2);
}

void LcmSink::OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) {
  publisher_->PublishMeshDelta(delta);
  publisher_->PublishFrameStats(stats);
  if (pose) publisher_->PublishCameraPose(stats.frame_id, stats.timestamp_s, *pose);
}

void LcmSink::OnFinish(const FrameStats& stats, const MeshDelta& final_delta) {
  publisher_->PublishMeshDelta(final_delta);
  publisher_->PublishFrameStats(stats);
  publisher_->Flush();
}

}  // namespace semap::io
