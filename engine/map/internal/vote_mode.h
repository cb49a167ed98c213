// Where the map's visibility votes come from (map.visibility), behind one interface: DepthVoteMode (each
// frame's depth map; depth_vote_mode.h) and RayVoteMode (one exact walk per point ray; ray_vote_mode.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/labelled_cloud.h"
#include "engine/map/incremental_map.h"
#include "engine/map/internal/map_state.h"
#include "engine/map/internal/region_carver.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/map_options.h"

namespace semap::map_internal {

// The steps of an update that depend on where the votes come from. IncrementalMap::Impl runs them in this
// order: CheckInput, Locate (LocateHeld for IncrementalMap::InsertHeldPoints), Insert, Vote, then, after the
// region carver, MarkSeenSurface; a finalisation calls ReleaseVotes before it removes the old vertices and
// RevoteReleased once the hole is refilled. A mode works on the MapState it was made with and keeps its own
// records (rays and cameras; depth views and held points). Not thread-safe.
class VoteMode {
 public:
  virtual ~VoteMode() = default;

  // Throws std::invalid_argument for a frame the mode cannot vote from (the map stays as it was).
  virtual void CheckInput(const LabelledCloud& frame, const std::vector<Observation>& extra) const = 0;
  // After MapState::BeginFrame: each frame point merged into the point it lands on, or pending insertion
  // as a new point (result->point_ids says which), and the Steiner nodes around them
  // (MapState::AddSteinerNodes): the pending vertices, in insertion order.
  virtual std::vector<PendingVertex> Locate(const LabelledCloud& frame, const std::vector<Observation>& extra,
                                            MapUpdateResult* result) = 0;
  // Whether points wait for a second sighting (map.confirm_beyond_m) that LocateHeld can insert.
  virtual bool HoldsPoints() const = 0;
  // After MapState::BeginUpdate: the held points pending insertion where their one sighting put them, with
  // their Steiner nodes; none is held afterwards.
  virtual std::vector<PendingVertex> LocateHeld(MapUpdateResult* result) = 0;
  // Inserts `pending`, leaving out those whose insertion would change a pinned cell (counted in
  // result->points_rejected_at_seam); the cells it creates carry update.created_mark, and update.boundary
  // lists the vertices around the cells it destroyed.
  virtual void Insert(std::vector<PendingVertex>* pending, MapUpdateResult* result) = 0;
  // The votes of the cells the update created or the frame sees; update.touched lists the cells the carving
  // must look at again.
  virtual void Vote(MapUpdateResult* result) = 0;
  // After the carving: the new surface facets the views saw marked seen (CellInfo::seen_facets).
  virtual void MarkSeenSurface() = 0;
  // A finalisation is about to remove the vertices of the points `finalised` (and Steiner vertices),
  // destroying update.destroyed (stamped `destroyed_mark`): what the mode recorded there is withdrawn.
  virtual void ReleaseVotes(const std::vector<std::uint32_t>& finalised, std::uint32_t destroyed_mark) = 0;
  // After that removal, update.touched begun: the cells filling the hole voted again, and those that lost
  // votes touched.
  virtual void RevoteReleased(MapUpdateResult* result) = 0;

  // The live map as batch-map input (IncrementalMap::ExportSnapshot).
  virtual MapSnapshot ExportSnapshot() const = 0;
  virtual std::size_t LiveRays() const = 0;
};

// The vote mode map.visibility names, on `state` (and `carver`, which must outlive it).
std::unique_ptr<VoteMode> MakeVoteMode(MapState& state, RegionCarver& carver);
// The surface facets the output of a map with `options` leaves out: only depth views see a facet as a
// surface, so only they drop the unseen ones.
EmitRule OutputRule(const MapOptions& options);

}  // namespace semap::map_internal
