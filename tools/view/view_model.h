// What `semap view` shows, shared between the source that fills it (a run folder, a mesh file, or a live LCM
// subscription) and the server that pushes it to every open page: the mesh (as one encoded binary message),
// the camera trajectory, the per-frame statistics and a status line.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/class_map.h"
#include "engine/core/mesh.h"

namespace semap::tools::view {

// One point of the statistics over time (a run's frames.jsonl line, or a live frame_stats_t).
struct StatsPoint {
  std::int64_t frame_id = 0;
  double elapsed_s = 0.0;      // seconds since the run's first frame entered
  double fps = 0.0;            // frames processed per second so far
  std::int64_t triangles = 0;  // mesh triangles
  std::int64_t vertices = 0;   // map vertices
};

// The left camera of one frame.
struct PosePoint {
  std::int64_t frame_id = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // camera centre, world frame
  Eigen::Quaterniond world_from_cam = Eigen::Quaterniond::Identity();
};

// The mesh as the page receives it: one binary WebSocket message, little-endian:
//   char[4] "SMV1"; uint32 vertices n; uint32 triangles m; uint32 flags (bit 0: per-vertex error present);
//   int64 frame id (-1: none);
//   float32 positions[3n] (m); float32 error_m[n] (if flag); uint32 indices[3m]; uint8 colours[3n] (RGB);
//   uint8 labels[n]
// `error_m` (distance of each vertex to a true surface), when given, has one value per vertex.
std::string EncodeMeshMessage(const Mesh& mesh, std::int64_t frame_id, const std::vector<float>* error_m);

// The description of the source the page receives first (JSON text): what is shown, the class map's palette
// (id, name, colour) and whether per-vertex error is available.
struct SourceInfo {
  std::string kind;          // "run", "mesh" or "live"
  std::string name;          // run folder, mesh file, or LCM URL with the channel prefix
  std::string up = "auto";   // world up axis for the page ("auto": the mesh's thinnest axis, y taken as down)
  bool has_error = false;    // the mesh messages carry per-vertex error
  std::string error_source;  // what the error is measured against (the true mesh's path)
};

// Thread-safe: every member may be called from any thread. Each part carries a version (or, for the
// append-only trajectory and statistics, a length) so that a reader can tell what it has not yet sent.
class ViewModel {
 public:
  explicit ViewModel(SourceInfo info, const ClassMap& class_map);

  // The hello message (JSON text): source, palette, error availability.
  const std::string& hello() const { return hello_; }

  void SetMesh(std::shared_ptr<const std::string> encoded, std::int64_t triangles, std::int64_t vertices);
  void AddStats(const StatsPoint& s);
  void AddPose(const PosePoint& p);
  void SetStatus(const std::string& text);
  // A new run: drops the mesh, trajectory and statistics (pages are told to clear theirs).
  void Reset();

  struct Snapshot {
    std::uint64_t epoch = 0;         // incremented by Reset
    std::uint64_t mesh_version = 0;  // 0: no mesh yet
    std::shared_ptr<const std::string> mesh;
    std::int64_t triangles = 0, vertices = 0;
    std::uint64_t status_version = 0;
    std::string status;
    size_t num_stats = 0, num_poses = 0;
  };
  Snapshot Get() const;
  // JSON text of the statistics / poses with indices in [from, to) (a "stats" / "poses" message), or "" if
  // none.
  std::string StatsSince(size_t from, size_t to) const;
  std::string PosesSince(size_t from, size_t to) const;

 private:
  std::string hello_;
  mutable std::mutex mutex_;
  std::uint64_t epoch_ = 0;                    // guarded by mutex_
  std::uint64_t mesh_version_ = 0;             // guarded by mutex_
  std::shared_ptr<const std::string> mesh_;    // guarded by mutex_
  std::int64_t triangles_ = 0, vertices_ = 0;  // guarded by mutex_
  std::uint64_t status_version_ = 0;           // guarded by mutex_
  std::string status_;                         // guarded by mutex_
  std::vector<StatsPoint> stats_;              // guarded by mutex_
  std::vector<PosePoint> poses_;               // guarded by mutex_
};

}  // namespace semap::tools::view
