// The state every step of the incremental map shares: the triangulation, its data points and Steiner
// vertices, the output's seams of finalisation, and what the steps of one update hand each other. One
// MapState per map, owned by IncrementalMap::Impl and passed by reference to the steps that use it (the
// vote mode, the region carver, the finaliser).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/core/labelled_cloud.h"
#include "engine/map/incremental_map.h"
#include "engine/map/internal/depth_filter.h"
#include "engine/map/internal/mesher.h"
#include "engine/map/internal/steiner_lattice.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/internal/triangulation.h"
#include "engine/map/map_options.h"

namespace semap::map_internal {

inline constexpr std::uint32_t kNoMark = 0xFFFFFFFFu;  // a stamp never given

// A pending insertion: a data point (id) or a Steiner node (node key).
struct PendingVertex {
  Eigen::Vector3d position;
  std::uint32_t point_id = kNoId;  // kNoId for a Steiner node
  LatticeKey node = 0;
  PointAttributes attributes;
};

// The label and colour of frame point i (defaults where the frame has none).
PointAttributes AttributesOf(const LabelledCloud& frame, std::uint32_t i);
// Sorts `pending` along a space-filling curve so consecutive insertions are neighbours (cheap locate).
void SpatialSort(std::vector<PendingVertex>* pending);

// A data point of the map, live from its creation to its finalisation.
struct PointRecord {
  VertexHandle vertex;  // none while it waits for its insertion
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // The frame its age counts from, for finalisation: its arrival, or (depth) the last frame that saw it
  // again, refreshed every finalise_every_frames (an arrival-queue entry that does not match it is stale).
  std::int64_t last_seen = 0;
  std::vector<std::uint32_t> rays;  // rays: its rays, the first one from its first camera
  std::uint32_t support = 1;        // depth: the observations merged into it, its own included
  // depth, map.fuse_gate_sigmas > 0: the fused estimate of its sightings (depth_filter.h).
  DepthFilter filter;
  // Where the output mesh puts its vertex once output_version > 0 (VertexInfo): the fused estimate as it
  // stood at the last bump.
  Eigen::Vector3d output_position = Eigen::Vector3d::Zero();
};

// A live point id with the frame it was last seen in (MapState::arrival).
struct Arrival {
  std::uint32_t id;
  std::int64_t frame;
};

// What the steps of one update hand each other. Each list is filled by the step named and read by those after
// it in the same update.
struct UpdateScratch {
  std::vector<LatticeKey> nodes;          // lattice nodes the update requires (BeginFrame, AddSteinerNodes)
  std::uint32_t created_mark = 0;         // CellInfo::created of the cells the update creates (BeginUpdate)
  std::vector<VertexHandle> inserted;     // vertices inserted (RecordInserted)
  std::vector<CellHandle> destroyed;      // cells (with votes) the change destroys
  std::vector<VertexHandle> boundary;     // their finite vertices
  std::vector<CellHandle> touched;        // cells whose votes or carving changed, stamped touch_mark (Touch)
  std::uint32_t touch_mark = 0;           // BeginTouched
  std::vector<CellHandle> carve_changed;  // RegionCarver::Regrow: cells whose carving it changed
};

// Not thread-safe. Not copyable: the steps and the mesher hold references to it.
struct MapState {
  MapState(const MapOptions& options, const EmitRule& emit);
  MapState(const MapState&) = delete;
  MapState& operator=(const MapState&) = delete;

  // A fresh mark for the stamps of one pass (CellInfo / VertexInfo stamp and created): never given before.
  std::uint32_t NewMark() { return ++last_mark; }

  // A new update: a fresh created_mark, no lattice nodes required yet.
  void BeginUpdate();
  // A new frame: BeginUpdate, the frame counted, the lattice nodes around its cameras required, the last of
  // them the latest camera.
  void BeginFrame(const LabelledCloud& frame);
  // Appends to `pending` the lattice nodes its points and the update's cameras require, and sorts it into
  // insertion order (SpatialSort).
  void AddSteinerNodes(std::vector<PendingVertex>* pending);
  // A new data point for frame point i, pending insertion (its record made, its age starting now).
  std::uint32_t NewPoint(const LabelledCloud& frame, std::uint32_t i, std::vector<PendingVertex>* pending);
  // Inserts `pending` one by one, each from the previous one's cell (no seam test: the caller has left out
  // the vertices that would change a pinned cell, or there is no seam yet).
  void InsertVertices(std::vector<PendingVertex>* pending, MapUpdateResult* result);
  // The bookkeeping of a vertex just inserted for `pv` (appended to update.inserted).
  void RecordInserted(const PendingVertex& pv, VertexHandle v, MapUpdateResult* result);
  // Drops the pending vertices flagged in `conflicts_pinned` (one entry per pending vertex: its insertion
  // would destroy a pinned cell, a seam of finalisation): their points are erased and their frame points
  // dropped (counted in `result`). Returns the number of frame points dropped; `dropped_ids` receives the
  // point ids.
  std::size_t DropPinnedConflicts(const std::vector<char>& conflicts_pinned,
                                  std::vector<PendingVertex>* pending, MapUpdateResult* result,
                                  std::unordered_set<std::uint32_t>* dropped_ids);

  // update.touched starts empty, with a fresh touch_mark.
  void BeginTouched();
  // Appends `c` to update.touched unless it is there (stamped touch_mark).
  void Touch(CellHandle c);
  // Marks as created in this update the cells incident to `vertices` not stamped `old_mark`, and appends
  // those it marks (not marked before) to `newly_marked` (may be null).
  void MarkCreatedCells(const std::vector<VertexHandle>& vertices, std::uint32_t old_mark,
                        std::vector<CellHandle>* newly_marked = nullptr);
  // Stamps every cell around `vertices` with a new mark, returned: after a removal, the cells around them
  // without it are the ones refilling the hole.
  std::uint32_t StampCellsAround(const std::vector<VertexHandle>& vertices);
  // update.boundary = the finite vertices of update.destroyed, except those stamped `excluded_vertex_mark`.
  void CollectBoundary(std::uint32_t excluded_vertex_mark);
  // Appends to update.boundary the finite vertices of `c` stamped neither `mark` nor
  // `excluded_vertex_mark`, and stamps them `mark`.
  void AddVerticesToBoundary(CellHandle c, std::uint32_t mark, std::uint32_t excluded_vertex_mark);
  // Appends to update.boundary those of `vertices` it does not hold.
  void AddToBoundary(const std::vector<VertexHandle>& vertices);

  // Where the output mesh puts vertex `v`: its fused estimate as of its last output bump, else its position
  // in the triangulation.
  Eigen::Vector3d OutputPosition(VertexHandle v) const;
  // The sizes of the map and its counters (MapStatistics), without the rays and the passes over every cell.
  MapStatistics Sizes() const;

  const MapOptions options;
  Delaunay dt;
  SteinerLattice lattice;
  std::unordered_map<std::uint32_t, PointRecord> points;  // the live data points, by id
  std::unordered_map<LatticeKey, VertexHandle> steiner;   // the Steiner vertices, by lattice node
  // Live point ids by the frame they were last seen in, oldest first (for finalisation by age). An entry
  // whose frame is not its point's last_seen (seen again since, or gone) is stale and skipped.
  std::deque<Arrival> arrival;
  std::uint32_t next_point_id = 0;
  std::uint32_t next_steiner_id = 0;
  std::int64_t frame = -1;  // the frame being mapped (counted from 0)
  Eigen::Vector3d last_camera = Eigen::Vector3d::Zero();
  std::uint32_t last_mark = 0;  // NewMark
  Mesher mesher;  // the output: live surface, finalised triangles, the vertex copies at the seams
  MapStatistics counters;
  UpdateScratch update;
};

}  // namespace semap::map_internal
