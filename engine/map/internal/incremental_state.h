// The state of the incremental map and its update steps (engine/map/incremental_map.cc drives them).
#pragma once

#include <algorithm>
#include <chrono>
#include <deque>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/map/incremental_map.h"
#include "engine/map/internal/depth_integrator.h"
#include "engine/map/internal/hole_cut.h"
#include "engine/map/internal/manifold_carver.h"
#include "engine/map/internal/mesher.h"
#include "engine/map/internal/ray_registry.h"
#include "engine/map/internal/ray_tracer.h"
#include "engine/map/internal/steiner_lattice.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// A pending insertion: a data point (id) or a Steiner node (node key).
inline constexpr std::uint32_t kNoMark = 0xFFFFFFFFu;  // a stamp never given

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
// Milliseconds since `*since`, which is moved to now.
double Lap(std::chrono::steady_clock::time_point* since);

class IncrementalState {
 public:
  explicit IncrementalState(const MapOptions& options);

  MapUpdateResult Update(const LabelledCloud& frame, const std::vector<Observation>& extra);
  // IncrementalMap::InsertHeldPoints.
  MapUpdateResult InsertHeld();
  IdentifiedMesh ExtractMesh() const { return mesher_.ExtractLive(); }
  IdentifiedMesh TakeFinalisedMesh() { return mesher_.TakeFinalised(); }
  std::vector<CellVotes> CellVotesSnapshot() const { return CollectCellVotes(dt_); }
  MapSnapshot ExportSnapshot() const;
  MapStatistics Statistics() const;
  MapStatistics Sizes() const;

 private:
  // map.visibility: depth. One frame: its points merged into the live vertices they land on (by projection
  // into their view) or inserted; the cells in its view voted from its depth map, the cells the insertion
  // created from the window of stored views; the manifold carved where a cell's free/matter state changed.
  MapUpdateResult UpdateFromDepth(const LabelledCloud& frame);
  // The steps after the merging: the Steiner nodes around `pending`, their conflict regions, the insertions,
  // the votes of the cells they create (and, with `newest_view_votes`, of the old cells the newest view
  // sees), the carving and the finalisation. `nodes`: the lattice nodes already in use by this update.
  void InsertAndVote(std::vector<PendingVertex>* pending, std::vector<LatticeKey>* nodes,
                     bool newest_view_votes, MapUpdateResult* result,
                     std::chrono::steady_clock::time_point* lap);
  // The frame's points that no live vertex explains (see MapOptions::merge_radius_px) go to `pending`; the
  // others add to the support of the vertex they land on.
  void ClassifyByProjection(const LabelledCloud& frame, MapUpdateResult* result,
                            std::vector<PendingVertex>* pending);
  // InsertVertices, each cell the insertion creates starting with the votes of the destroyed cell it was
  // built on (the one inside the hole across its facet opposite the new vertex): what the map knew there.
  // A point whose conflict region holds a pinned cell carved across a facet is not inserted and flagged in
  // `conflicts_pinned` (one entry per pending vertex; DropPinnedConflicts drops it). Counts in
  // result->cells_destroyed the cells of the triangulation before the pass that it destroys; boundary_ =
  // their finite vertices.
  void InsertVerticesInheriting(std::vector<PendingVertex>* pending, MapUpdateResult* result,
                                std::vector<char>* conflicts_pinned);
  // A pending data point exactly at `existing`: its frame points become that point (or are dropped, on a
  // Steiner vertex).
  void MergeCoincident(const PendingVertex& pv, VertexHandle existing, MapUpdateResult* result);
  // A point seen again (kDepth): more support, and its age restarts.
  void SeenAgain(std::uint32_t id);
  // Where the output mesh puts vertex `v`: its fused estimate as of its last output bump (FilterVertex), else
  // its position in the triangulation.
  Eigen::Vector3d OutputPosition(VertexHandle v) const;
  // map.fuse_gate_sigmas > 0 (and a depth noise model): each live vertex is the fused estimate of its
  // sightings (depth_filter.h).
  bool Fusing() const { return options_.fuse_gate_sigmas > 0.0 && options_.disparity_sigma_px > 0.0; }
  // The sighting of live vertex `v` by `view` added to its depth filter. A vertex more views saw through
  // than saw (map.outlier_sightings) leaves the map; one whose estimate moved away from it (beyond
  // map.fuse_move_sigmas of its σ) is replaced by a vertex at the estimate, pending insertion with a new
  // point id. Both are listed in refined_ for removal (only when Refinable). Returns the id the frame's
  // points landing on it merge into: its own, its successor's, or kNoId when it leaves the map.
  std::uint32_t FilterVertex(VertexHandle v, const VotingView& view, MapUpdateResult* result,
                             std::vector<PendingVertex>* pending);
  // Whether the vertex of point `id` may be refined (MapOptions::refine_depth_ratio): live, neither frozen
  // nor left irregular, and no pinned cell around it (its removal must not change a seam).
  bool Refinable(std::uint32_t id) const;
  // Removes the vertices of refined_ (their successors are pending insertion): the cells refilling their
  // holes are marked created (created_mark_) and the vertices around them listed in refined_link_.
  void RemoveRefined(MapUpdateResult* result);
  // Appends to boundary_ those of `vertices` it does not hold.
  void AddToBoundary(const std::vector<VertexHandle>& vertices);
  // Stamps every cell around `vertices` with a new mark, returned: after a removal, the cells around them
  // without it are the ones refilling the hole.
  std::uint32_t StampCellsAround(const std::vector<VertexHandle>& vertices);
  // kDepth: marks the cells around the inserted vertices created and lists every cell this update created
  // (those of a refinement's removal too) in created_cells_.
  void CollectCreatedCells();

  // A new data point for frame point i, pending insertion (its record made, its age starting now).
  std::uint32_t NewPoint(const LabelledCloud& frame, std::uint32_t i, std::vector<PendingVertex>* pending);

  // Update steps.
  void ClassifyPoints(const LabelledCloud& frame, const std::vector<std::uint32_t>& camera_ids,
                      MapUpdateResult* result, std::vector<PendingVertex>* pending,
                      std::vector<std::pair<std::uint32_t, std::uint32_t>>* new_rays);
  // destroyed_ = the cells in conflict with `pending`, except for the vertices whose conflict zone holds a
  // pinned cell: those are flagged in `conflicts_pinned` (one entry per pending vertex). map.visibility:
  // rays, whose rays through destroyed_ are untraced before the insertions; the depth path finds the same
  // while inserting (InsertVerticesInheriting).
  void CollectConflicts(const std::vector<PendingVertex>& pending, std::vector<char>* conflicts_pinned);
  // boundary_ = the finite vertices of destroyed_, except those stamped `excluded_vertex_mark`.
  void CollectBoundary(std::uint32_t excluded_vertex_mark);
  // Appends to boundary_ the finite vertices of `c` stamped neither `mark` nor `excluded_vertex_mark`, and
  // stamps them `mark`.
  void AddVerticesToBoundary(CellHandle c, std::uint32_t mark, std::uint32_t excluded_vertex_mark);
  // Uncarves the touched cells that are no longer free, then repairs the manifold around them (greedy
  // growth; carve-and-repair leaves their vertices in repair_later_ for Regrow).
  std::size_t ShrinkNonFree();
  // The live rays listed in destroyed_ (appended to `affected`, marked with the returned mark).
  std::uint32_t CollectAffectedRays(std::vector<std::uint32_t>* affected);
  // Marks as created in this update the cells incident to `vertices` not stamped `old_mark`, and appends
  // those it marks (not marked before) to `newly_marked` (may be null).
  void MarkCreatedCells(const std::vector<VertexHandle>& vertices, std::uint32_t old_mark,
                        std::vector<CellHandle>* newly_marked = nullptr);
  void InsertVertices(std::vector<PendingVertex>* pending, MapUpdateResult* result);
  // The bookkeeping of a vertex just inserted for `pv` (appended to inserted_).
  void RecordInserted(const PendingVertex& pv, VertexHandle v, MapUpdateResult* result);
  // Ray votes: sign +1 traces `rays` (adds votes and cell entries), -1 untraces them (and lists the cells in
  // decreased_; the rays' epochs move on, so their cell entries become stale). The walks run in parallel
  // (they only read the triangulation) and the votes are applied in the order of `rays`, so the result does
  // not depend on the thread count. With `only_created`, the votes go to the cells created in this update
  // only (and the walks stop past the ray's span): the ray's votes in the cells that survived the change
  // are still there (same cell, same point, same weight).
  void TraceRays(const std::vector<std::uint32_t>& rays, int sign, bool only_created = false);
  // The greedy growth restarts around the re-triangulated region: uncarves the stars of boundary_ (appended
  // to `uncarved`). Carve-and-repair does not need it.
  void UncarveBoundaryStars(std::vector<CellHandle>* uncarved);
  // Carves the free cells of touched_ and makes the manifold whole again around them and boundary_; lists in
  // carve_changed_ the cells whose carving that changed beyond touched_.
  std::size_t Regrow();
  // kDepth, map.drop_unseen_surface: the unseen surface facets of the cells this update created or changed
  // the carving of (touched_, carve_changed_), looked for in the window's views (DepthIntegrator::
  // MarkSeenSurface); the cells marked go to newly_seen_.
  void MarkSeenSurface();
  void Finalise(MapUpdateResult* result);
  // The last steps of both updates (rays, depth) once the votes are in: uncarve the touched cells no longer
  // free, regrow, finalise, take the irregular vertices; carve_ms and finalise_ms timed from `lap`.
  void CarveAndFinalise(MapUpdateResult* result, std::chrono::steady_clock::time_point* lap);
  // Drops the pending vertices whose insertion would destroy a pinned cell (a seam of finalisation): their
  // points are dropped (counted in `result`) with their rays. Returns the number dropped.
  std::size_t DropPinnedConflicts(const std::vector<char>& conflicts_pinned,
                                  std::vector<PendingVertex>* pending,
                                  std::vector<std::pair<std::uint32_t, std::uint32_t>>* new_rays,
                                  MapUpdateResult* result);
  // kDepth, map.fill_unseen_holes_facets: marks seen the small holes of unseen surface facets ringed by seen
  // ones around the cells whose carving or seen facets this update changed (see seen_holes.h).
  void FillSeenHoles();
  // Hands the vertices the carver could not repair to the mesher.
  void TakeIrregular();

  // The two halves of a trace: the walk (const, safe to run concurrently) and the bookkeeping.
  bool ComputeVotes(std::uint32_t ray, bool only_created, RayVotes* votes) const;
  void ApplyVotes(std::uint32_t ray, int sign, const RayVotes& votes);
  std::uint32_t NewMark() { return ++mark_; }
  // The surface facets the output leaves out (live mesh and finalised triangles alike).
  EmitRule Emit() const {
    return {options_.drop_steiner_triangles,
            options_.visibility == Visibility::kDepth && options_.drop_unseen_surface};
  }

  MapOptions options_;
  RayGeometry geometry_;
  Delaunay dt_;
  ManifoldCarver carver_;
  DepthIntegrator integrator_;  // kDepth: the window of views and their votes
  SteinerLattice lattice_;
  RayRegistry rays_;
  std::unordered_map<std::uint32_t, PointRecord> points_;
  std::unordered_map<std::uint32_t, CameraRecord> cameras_;
  std::unordered_map<LatticeKey, VertexHandle> steiner_;
  // Live point ids by the frame they were last seen in, oldest first (for finalisation by age). An entry
  // whose frame is not its point's last_seen (seen again since, or gone) is stale and skipped.
  struct Arrival {
    std::uint32_t id;
    std::int64_t frame;
  };
  std::deque<Arrival> arrival_;
  std::uint32_t next_point_id_ = 0;
  std::uint32_t next_camera_id_ = 0;
  std::uint32_t next_steiner_id_ = 0;
  std::int64_t frame_ = -1;
  std::uint32_t mark_ = 0;
  std::uint32_t touch_mark_ = 0;
  std::uint32_t created_mark_ = 0;
  Eigen::Vector3d last_camera_ = Eigen::Vector3d::Zero();

  // Scratch of one update.
  std::vector<CellHandle> destroyed_;   // cells (with votes) the change destroys
  std::vector<VertexHandle> boundary_;  // their vertices
  std::vector<CellHandle> touched_;     // cells whose votes or carving changed
  std::vector<CellHandle> decreased_;   // cells that lost votes (untraced rays)
  std::vector<VertexHandle> inserted_;  // vertices inserted in this update
  // kDepth, map.confirm_beyond_m: far points of the last confirm_window_frames frames waiting for a second
  // sighting, oldest first.
  struct Unconfirmed {
    Eigen::Vector3d position;
    PointAttributes attributes;
    double depth_m;      // camera-frame depth of the sighting
    std::int64_t frame;  // the frame that saw it
  };
  std::vector<Unconfirmed> unconfirmed_;
  std::vector<std::uint32_t> refined_;      // kDepth: points whose vertex a nearer sighting replaces
  std::vector<VertexHandle> refined_link_;  // the vertices around the refined ones removed
  std::vector<CellHandle> conflict_scratch_;
  std::vector<VertexHandle> repair_later_;  // vertices ShrinkNonFree leaves to Regrow's repair
  std::vector<CellHandle> created_cells_;   // kDepth: the cells this update created (CollectCreatedCells)
  std::vector<CellHandle> newly_seen_;      // kDepth: cells the integrator marked facets of seen
  std::vector<CellHandle> carve_changed_;   // Regrow: cells whose carving it changed (may repeat touched_)

  Mesher mesher_;  // the output: live surface, finalised triangles
  MapStatistics counters_;
};

}  // namespace semap::map_internal
