// The incremental Delaunay map used by the pipeline: per frame, new points and rays update only the region
// they affect; regions far behind the camera are finalised and released (memory bound).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh.h"
#include "engine/core/mesh_delta.h"
#include "engine/map/map_options.h"
#include "engine/map/map_types.h"

namespace semap {

inline constexpr std::uint32_t kDroppedPoint = 0xFFFFFFFFu;

struct MapUpdateResult {
  // Per input point: the id of the point it became or was merged into, or kDroppedPoint (beyond
  // max_ray_length_m, or held for confirmation: map.confirm_beyond_m). Ids name points in later Observations.
  std::vector<std::uint32_t> point_ids;
  std::size_t inserted = 0;  // new vertices (data points)
  std::size_t merged = 0;    // points merged into an existing one (their ray added)
  std::size_t dropped = 0;
  // Of `dropped`: points whose insertion would have re-triangulated a seam of finalisation (cells kept
  // as they are so that the emitted and the live surface stay one manifold).
  std::size_t points_rejected_at_seam = 0;
  std::size_t steiner_inserted = 0;
  std::size_t cells_destroyed = 0;  // cells with votes replaced by the insertion
  std::size_t rays_retraced = 0;    // existing rays untraced and traced again
  std::size_t rays_traced = 0;      // new rays
  std::size_t cells_voted = 0;      // map.visibility: depth: cells that got votes from the frame's views
  std::size_t cells_uncarved = 0;   // local shrink
  std::size_t cells_carved = 0;     // local growth
  std::size_t points_finalised = 0;
  std::size_t vertices_removed = 0;  // finalised points and released Steiner vertices
  // kDepth, map.fuse_gate_sigmas: vertices moved to their fused estimate (replaced by a vertex there), and
  // vertices the views saw through that left the map (map.outlier_sightings).
  std::size_t vertices_moved = 0;
  std::size_t vertices_outliers = 0;
  // kDepth, map.fuse_output_sigmas: vertices the output moved to their fused estimate (no re-triangulation).
  std::size_t vertices_output_moved = 0;
  // kDepth, map.confirm_beyond_m: far points held for a second sighting (not in point_ids' vertices), and
  // held points of earlier frames that this frame confirmed (each became a vertex).
  std::size_t points_held = 0;
  std::size_t points_confirmed = 0;
  // InsertHeldPoints: the held points that became vertices unconfirmed.
  std::size_t points_held_inserted = 0;
  // Wall time of the update's steps.
  // Merging the points into live vertices (depth: and the vertices' fused moves and removals); rays: also the
  // conflict regions and the rays through them.
  double locate_ms = 0.0;
  double insert_ms =
      0.0;  // vertex insertion into the triangulation (depth: with each point's conflict region)
  double trace_ms = 0.0;     // the votes: retracing the affected rays and tracing the new ones (rays), or
                             // voting the cells from the views (depth)
  double carve_ms = 0.0;     // shrinking and regrowing the manifold free space
  double finalise_ms = 0.0;  // finalising and releasing old parts (every finalise_every_frames frames)
};

// The live map as batch-map input: cloud point i is live point `point_ids[i]`; its first camera is the camera
// of its first ray, its other rays are `extra` observations. Cameras are the live ones.
struct MapSnapshot {
  LabelledCloud cloud;
  std::vector<Observation> extra;
  std::vector<std::uint32_t> point_ids;
};

// Not thread-safe: one thread calls Update and the readers, in turn.
class IncrementalMap {
 public:
  explicit IncrementalMap(const MapOptions& options);  // throws InvalidOption
  ~IncrementalMap();
  IncrementalMap(IncrementalMap&&) noexcept;
  IncrementalMap& operator=(IncrementalMap&&) noexcept;

  // One frame: `frame_points` with their cameras (camera_index into frame_points.camera_centers_world,
  // usually the frame's one camera), plus `extra` rays to existing points (Observation.point = an id from an
  // earlier update, Observation.camera indexes frame_points.camera_centers_world). A point within
  // merge_distance_m of an existing point (or of an earlier point of the frame) is merged: its ray goes to
  // that point. Throws std::invalid_argument for an unknown point id in `extra`.
  MapUpdateResult Update(const LabelledCloud& frame_points, const std::vector<Observation>& extra = {});
  // At the end of a stream (map.visibility: depth, map.confirm_beyond_m > 0): the far points still held for a
  // second sighting become vertices as their one sighting placed them, since no later frame will come to
  // confirm them; their cells are voted from the stored views. Without it they would be dropped: a one-frame
  // map would have no far surface at all. Leaves the map as it was when nothing is held.
  MapUpdateResult InsertHeldPoints();

  // The current live surface (Steiner triangles dropped if the options say so).
  Mesh ExtractMesh() const;
  // The live surface with stable vertex ids (point ids; Steiner vertices have bit 63 set): feed it to a
  // MeshDiffer (engine/core/mesh_delta.h) with TakeFinalisedMesh() as `frozen` to stream mesh deltas.
  IdentifiedMesh ExtractIdentifiedMesh() const;
  // Triangles of finalised regions not yet taken, with the same vertex ids; each finalised triangle is
  // returned exactly once (they left the live surface for good).
  IdentifiedMesh TakeFinalisedMesh();

  std::vector<CellVotes> CellVotesSnapshot() const;
  MapSnapshot ExportSnapshot() const;
  MapStatistics Statistics() const;
  // Statistics() without num_carved_cells and num_free_cells (left 0), which take a pass over every cell:
  // cheap enough to report every frame.
  MapStatistics Sizes() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semap
