// map.visibility: depth (the default): the votes come from each frame's depth map. A frame's points merge
// into the live vertices they land on in its view, or become new vertices (far ones once a second sighting
// confirms them); each live vertex fuses its sightings; the cells an insertion creates are voted from the
// window of stored views, the old cells the newest view sees from it (depth_integrator.h); only the surface
// facets some view saw are output.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/map/internal/depth_integrator.h"
#include "engine/map/internal/held_points.h"
#include "engine/map/internal/projection_grid.h"
#include "engine/map/internal/vote_mode.h"

namespace semap::map_internal {

// One update: Locate puts the frame's views in the window, merges its points by projection (fusing the
// sightings of the vertices they land on, holding the far ones), and removes the vertices that moved or that
// the views see through; Insert inserts the points, each new cell inheriting the votes of the cell it was
// built on; Vote votes the created cells from every view of the window and the old cells in the newest
// view from it; MarkSeenSurface looks for the new surface facets in the views and fills small holes. Owns
// the window of views and the held points. Not thread-safe (the votes run on TBB's workers).
class DepthVoteMode : public VoteMode {
 public:
  explicit DepthVoteMode(MapState& state);

  void CheckInput(const LabelledCloud& frame, const std::vector<Observation>& extra) const override;
  std::vector<PendingVertex> Locate(const LabelledCloud& frame, const std::vector<Observation>& extra,
                                    MapUpdateResult* result) override;
  bool HoldsPoints() const override { return !held_.empty() && !integrator_.views().empty(); }
  std::vector<PendingVertex> LocateHeld(MapUpdateResult* result) override;
  void Insert(std::vector<PendingVertex>* pending, MapUpdateResult* result) override;
  void Vote(MapUpdateResult* result) override;
  void MarkSeenSurface() override;
  // The votes live in the cells only, and go with them; the cells refilling the hole are sealed, and the
  // integrator skips sealed cells.
  void ReleaseVotes(const std::vector<std::uint32_t>&, std::uint32_t) override {}
  void RevoteReleased(MapUpdateResult*) override {}
  // Throws std::logic_error: a snapshot is batch-map input, whose points need their rays (map.visibility:
  // rays).
  MapSnapshot ExportSnapshot() const override;
  std::size_t LiveRays() const override { return 0; }

 private:
  // Where a frame point lands in its view (ProjectionGrid::Locate).
  struct Landing {
    bool in_view = false;
    int gu = 0, gv = 0;
    double depth_m = 0.0;
  };

  // The frame's points that no live vertex explains (see MapOptions::merge_radius_px) go to the returned
  // pending vertices; the others add to the support of the vertex they land on.
  std::vector<PendingVertex> ClassifyByProjection(const LabelledCloud& frame, MapUpdateResult* result);
  // Fills `grid` (of `view`) with the live vertices the view sees, each in the cell it projects to, after its
  // sighting is fused (FilterVertex). Vertices stamped `removing_mark` (listed for removal by an earlier
  // camera) are passed over; those listed now get the stamp.
  void ProjectLiveVertices(const VotingView& view, std::uint32_t removing_mark, ProjectionGrid* grid,
                           MapUpdateResult* result, std::vector<PendingVertex>* pending);
  // Frame point i: dropped (beyond map.max_ray_length_m), merged into the vertex it lands on in `grid` (its
  // camera's), held, confirming a held point, or a new point. Returns its point id, or kDroppedPoint.
  std::uint32_t ClassifyPoint(const LabelledCloud& frame, std::uint32_t i, const VotingView& view,
                              ProjectionGrid* grid, MapUpdateResult* result,
                              std::vector<PendingVertex>* pending);
  // A far point that no live vertex explains (map.confirm_beyond_m): it confirms the held point it lands on
  // (the pair becomes one new point at their mean weighted by 1/σ_z², σ_z ∝ z²), or merges into the point
  // that held point became this frame, or is held. Returns its point id, or kDroppedPoint when held.
  std::uint32_t ConfirmOrHold(const LabelledCloud& frame, std::uint32_t i, const VotingView& view,
                              std::size_t camera, const Landing& at, ProjectionGrid* grid,
                              MapUpdateResult* result, std::vector<PendingVertex>* pending);
  // Frame point i as a new point, its depth filter started from its sighting when `at` is in view.
  std::uint32_t NewSightedPoint(const LabelledCloud& frame, std::uint32_t i, const VotingView& view,
                                const Landing& at, ProjectionGrid* grid, std::vector<PendingVertex>* pending);
  // A point seen again: more support, and its age restarts.
  void SeenAgain(std::uint32_t id);
  // map.fuse_gate_sigmas > 0 (and a depth noise model): each live vertex is the fused estimate of its
  // sightings (depth_filter.h).
  bool Fusing() const {
    return state_.options.fuse_gate_sigmas > 0.0 && state_.options.disparity_sigma_px > 0.0;
  }
  // The sighting of live vertex `v` by `view` added to its depth filter. A vertex more views saw through
  // than saw (map.outlier_sightings) leaves the map; one whose estimate moved away from it (beyond
  // map.fuse_move_sigmas of its σ) is replaced by a vertex at the estimate, pending insertion with a new
  // point id. Both are listed in removing_ (only when Removable). Returns the id the frame's points landing
  // on it merge into: its own, its successor's, or kNoId when it leaves the map.
  std::uint32_t FilterVertex(VertexHandle v, const VotingView& view, MapUpdateResult* result,
                             std::vector<PendingVertex>* pending);
  // Whether the vertex of point `id` may be removed this frame: live, neither frozen nor left irregular, and
  // no pinned cell around it (its removal must not change a seam).
  bool Removable(std::uint32_t id) const;
  // Removes the vertices of removing_ (moved or outliers; the successors of the moved ones are pending
  // insertion): the cells refilling their holes are marked created (update.created_mark) and the vertices
  // around them listed in removed_link_.
  void RemoveVertices(MapUpdateResult* result);
  // Inserts `pending`, each cell the insertion creates starting with the votes of the destroyed cell it was
  // built on (the one inside the hole across its facet opposite the new vertex): what the map knew there.
  // A point whose conflict region holds a pinned cell carved across a facet is not inserted and flagged in
  // `conflicts_pinned` (one entry per pending vertex). Counts in result->cells_destroyed the cells of the
  // triangulation before the pass that it destroys; update.boundary = their finite vertices.
  void InsertInheriting(std::vector<PendingVertex>* pending, MapUpdateResult* result,
                        std::vector<char>* conflicts_pinned);
  // A pending data point exactly at `existing`: its frame points become that point (or are dropped, on a
  // Steiner vertex).
  void MergeCoincident(const PendingVertex& pv, VertexHandle existing, MapUpdateResult* result);
  // Marks the cells around the inserted vertices created and lists every cell this update created (those of
  // the removals too) in created_cells_.
  void CollectCreatedCells();
  // map.fill_unseen_holes_facets: marks seen the small holes of unseen surface facets ringed by seen ones
  // around the cells whose carving or seen facets this update changed (see seen_holes.h).
  void FillSeenHoles();

  MapState& state_;
  DepthIntegrator integrator_;  // the window of views and their votes
  HeldPoints held_;
  bool newest_view_votes_ = true;  // false when the update adds no frame (LocateHeld)

  // Scratch of one update.
  std::vector<std::uint32_t> removing_;     // points whose vertex this frame removes
  std::vector<VertexHandle> removed_link_;  // the vertices around the removed ones
  std::vector<CellHandle> created_cells_;   // the cells this update created (CollectCreatedCells)
  std::vector<CellHandle> newly_seen_;      // cells the integrator marked facets of seen
};

}  // namespace semap::map_internal
