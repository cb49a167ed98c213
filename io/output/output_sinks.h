// Pipeline sinks that write the run's results: the mesh (PLY/OFF), per-frame stats (CSV + JSON lines and a
// summary JSON), and the LCM publisher adapter. Each is called from the pipeline's output thread only.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>

#include "engine/core/mesh_delta.h"
#include "engine/core/options.h"
#include "engine/pipeline/pipeline.h"
#include "io/lcm/lcm_publisher.h"
#include "io/output/mesh_spill.h"

namespace semap::io {

struct OutputOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  std::string dir = "semap_out";
  bool mesh_ply = true;
  bool mesh_off = true;
  bool ply_ascii = false;
  bool frame_stats = true;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("dir", &dir, "output folder (mesh.ply, mesh.off, frames.csv, frames.jsonl, summary.json)",
            NotEmpty());
    v.Field("mesh_ply", &mesh_ply,
            "write the final mesh as PLY (binary unless ply_ascii) with colour and label");
    v.Field("mesh_off", &mesh_off, "write the final mesh as ASCII OFF (the paper's size measure)");
    v.Field("ply_ascii", &ply_ascii, "ASCII PLY instead of binary little-endian");
    v.Field("frame_stats", &frame_stats, "per-frame statistics as frames.csv and frames.jsonl");
  }

  void Check() const { CheckDeclaredRanges(*this); }
};

// Accumulates the mesh deltas and writes the final mesh at the end of the run, each file atomically (a
// temporary name renamed into place). The triangles the map finalised (MeshDelta::finalised_triangle_ids)
// leave its memory as they come, for a spill file in the folder (MeshSpill), so that its memory follows the
// live mesh, not the length of the drive; at the end they are read back and the whole mesh is written
// (triangles and vertices in the order of their ids, as MeshAccumulator::ToMesh would give them). When the
// spill file cannot be written, the finalised triangles stay in memory from then on (spill_error() says why)
// and nothing is lost. The constructor checks that the folder is writable; a mesh file that cannot be written
// at the end throws FileError (naming the path): the pipeline records it and goes on.
class MeshFileSink : public PipelineSink {
 public:
  explicit MeshFileSink(const OutputOptions& options);
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override;
  void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) override;
  // The whole mesh (after OnFinish; empty before).
  const Mesh& mesh() const { return mesh_; }
  // Written files (after OnFinish).
  const std::vector<std::filesystem::path>& written() const { return written_; }
  // The triangles held in memory now (the live mesh) and those moved to the spill file so far.
  std::size_t num_triangles_in_memory() const { return accumulator_.num_triangles(); }
  std::uint64_t num_triangles_spilled() const { return spill_.num_triangles(); }
  // Why the finalised triangles stopped going to the spill file ("" while they go there).
  const std::string& spill_error() const { return spill_error_; }

  // The spill file's name in the output folder (removed at the end of the run).
  static constexpr const char* kSpillFileName = ".mesh_finalised.spill";

 private:
  // The whole mesh: the spilled triangles and the live ones.
  Mesh AssembleMesh();

  OutputOptions options_;
  MeshAccumulator accumulator_;
  MeshSpill spill_;
  std::string spill_error_;
  Mesh mesh_;
  std::vector<std::filesystem::path> written_;
};

// A figure of a frame measured outside the pipeline's stages (e.g. by visual odometry in the reader: features
// tracked, inliers, time): one frames.csv column per name.
struct FrameFigure {
  std::string name;
  double value = 0.0;
};
// The figures of a frame by its id (the same names in the same order for every frame), called from the
// sink's thread: the source must be safe to call from there while the frames are read.
using FrameFigureSource = std::function<std::vector<FrameFigure>(std::int64_t frame_id)>;

// frames.csv + frames.jsonl (one line per integrated frame: its figures, its latency per step, the drops so
// far by reason) and summary.json at the end (with the run's latency per step: mean, p50, p95, max); frames
// that failed or were dropped go to errors.jsonl, a line each. The constructor checks that the folder is
// writable (throws FileError naming it); the per-frame files are opened (and a previous run's files replaced)
// at the first frame, so that a run that fails to start leaves them alone. They are written in place and
// flushed every frame (they can be followed live and keep every frame when the process dies); summary.json is
// written last, atomically, and removed when the run starts: a folder without it holds a run that did not
// finish.
class StatsFileSink : public PipelineSink {
 public:
  explicit StatsFileSink(const OutputOptions& options);
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override;
  void OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) override;
  void OnFrameDropped(std::int64_t frame_id, double timestamp_s, const std::string& reason) override;
  void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) override;
  // Adds the figures of `source` to each frame's line (columns named by the first frame's figures); before
  // the first frame.
  void SetFigureSource(FrameFigureSource source) { figure_source_ = std::move(source); }

 private:
  void OpenOnce();

  std::filesystem::path dir_;
  bool opened_ = false;
  std::ofstream csv_;
  std::ofstream jsonl_;
  std::ofstream errors_;
  bool header_written_ = false;
  FrameFigureSource figure_source_;
  std::vector<std::string> figure_columns_;  // the figures named in the header
  std::vector<std::string> drop_columns_;    // the drop reasons named in the header
};

// Publishes every mesh delta, frame stats and camera pose. Never blocks (see LcmPublisher).
class LcmSink : public PipelineSink {
 public:
  explicit LcmSink(std::unique_ptr<LcmPublisher> publisher) : publisher_(std::move(publisher)) {}
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override;
  void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) override;
  LcmPublisher& publisher() { return *publisher_; }

 private:
  std::unique_ptr<LcmPublisher> publisher_;
};

// The summary of a run as JSON text (fps, totals, per-stage timing): what summary.json holds.
std::string SummaryJson(const FrameStats& stats);

}  // namespace semap::io
