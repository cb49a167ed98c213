// map.visibility: rays: one exact walk per point ray through the triangulation (the paper's votes, the
// reference; any input, SfM tracks too). Each ray is recorded in the cells it crosses, and retraced where an
// insertion or a finalisation rebuilds them.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/map/internal/ray_registry.h"
#include "engine/map/internal/ray_tracer.h"
#include "engine/map/internal/vote_mode.h"

namespace semap::map_internal {

// One update: Locate merges each frame point into an existing point within map.merge_distance_m (its ray
// goes to it) or makes it a new point, finds the cells the insertions will destroy and the rays through
// them (untraced there by Vote's retrace: a retrace votes the new cells only); Insert inserts the points;
// Vote retraces those rays and traces the new ones. Owns the rays and cameras; not thread-safe (the walks
// run on TBB's workers, reading only).
class RayVoteMode : public VoteMode {
 public:
  RayVoteMode(MapState& state, RegionCarver& carver);

  void CheckInput(const LabelledCloud& frame, const std::vector<Observation>& extra) const override;
  std::vector<PendingVertex> Locate(const LabelledCloud& frame, const std::vector<Observation>& extra,
                                    MapUpdateResult* result) override;
  bool HoldsPoints() const override { return false; }  // every point is inserted at once
  std::vector<PendingVertex> LocateHeld(MapUpdateResult*) override { return {}; }
  void Insert(std::vector<PendingVertex>* pending, MapUpdateResult* result) override;
  void Vote(MapUpdateResult* result) override;
  void MarkSeenSurface() override {}  // rays see no facet as a surface: every surface facet is output
  void ReleaseVotes(const std::vector<std::uint32_t>& finalised, std::uint32_t destroyed_mark) override;
  void RevoteReleased(MapUpdateResult* result) override;
  MapSnapshot ExportSnapshot() const override;
  std::size_t LiveRays() const override { return rays_.num_live(); }

 private:
  // Records the frame's cameras (camera_ids_: the id of each).
  void AddCameras(const LabelledCloud& frame);
  // Each frame point beyond map.max_ray_length_m is dropped; one within merge_distance_m of a live vertex or
  // of an earlier new point of the frame merges into it; any other is a new point, pending insertion. The
  // ray of each kept point goes to new_rays_.
  void ClassifyPoints(const LabelledCloud& frame, MapUpdateResult* result,
                      std::vector<PendingVertex>* pending);
  // The point `p` merges into (see ClassifyPoints), or kNoId. `grid`: the frame's new points by voxel;
  // `hint`: where the last nearest-vertex search ended.
  std::uint32_t MergeTarget(const Eigen::Vector3d& p,
                            const std::unordered_map<std::int64_t, std::vector<std::uint32_t>>& grid,
                            CellHandle* hint) const;
  // update.destroyed = the cells in conflict with `pending`, less the vertices whose conflict zone holds a
  // pinned cell carved across a facet: those are dropped (with their rays); then the rays through the
  // destroyed cells (affected_), with the span of the region along each.
  void FindConflicts(std::vector<PendingVertex>* pending, MapUpdateResult* result);
  // update.destroyed = the cells in conflict with `pending`, except for the vertices whose conflict zone
  // holds a pinned cell: those are flagged in `conflicts_pinned` (one entry per pending vertex).
  void CollectConflicts(const std::vector<PendingVertex>& pending, std::vector<char>* conflicts_pinned);
  // The live rays listed in update.destroyed (appended to `affected`, marked with the returned mark).
  std::uint32_t CollectAffectedRays(std::vector<std::uint32_t>* affected);
  // Registers the rays of new_rays_; returns them.
  std::vector<std::uint32_t> AddNewRays();
  // Ray votes: sign +1 traces `rays` (adds votes and cell entries), -1 untraces them (and lists the cells in
  // decreased_; the rays' epochs move on, so their cell entries become stale). The walks run in parallel
  // (they only read the triangulation) and the votes are applied in the order of `rays`, so the result does
  // not depend on the thread count. With `only_created`, the votes go to the cells created in this update
  // only (and the walks stop past the ray's span): the ray's votes in the cells that survived the change
  // are still there (same cell, same point, same weight).
  void TraceRays(const std::vector<std::uint32_t>& rays, int sign, bool only_created = false);
  // The two halves of a trace: the walk (const, safe to run concurrently) and the bookkeeping.
  bool ComputeVotes(std::uint32_t ray, bool only_created, RayVotes* votes) const;
  void ApplyVotes(std::uint32_t ray, int sign, const RayVotes& votes);

  MapState& state_;
  RegionCarver& carver_;
  RayGeometry geometry_;
  RayRegistry rays_;
  std::unordered_map<std::uint32_t, CameraRecord> cameras_;
  std::uint32_t next_camera_id_ = 0;

  // Scratch of one update.
  std::vector<std::uint32_t> camera_ids_;                          // the frame's cameras (AddCameras)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> new_rays_;  // (point id, camera id), Locate
  std::vector<std::uint32_t> affected_;  // live rays through the destroyed cells, retraced
  std::vector<CellHandle> conflict_scratch_;
  std::vector<CellHandle> decreased_;   // cells that lost votes (untraced rays)
  std::vector<CellHandle> lost_;        // ReleaseVotes: surviving cells that lost votes
  std::vector<std::uint32_t> retrace_;  // ReleaseVotes: rays through the hole that stay live
};

}  // namespace semap::map_internal
