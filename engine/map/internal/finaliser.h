// The memory bound of the incremental map: the parts the drive has left behind are finalised (their surface
// emitted once) and released from the triangulation; the cells refilling the hole are sealed and the seam's
// vertices frozen, so that the emitted and the live surface stay one manifold (hole_cut.h).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/map/internal/hole_cut.h"
#include "engine/map/internal/map_state.h"
#include "engine/map/internal/region_carver.h"
#include "engine/map/internal/steiner_lattice.h"
#include "engine/map/internal/vote_mode.h"

namespace semap::map_internal {

// Works on the MapState, RegionCarver and VoteMode it is made with. Not thread-safe.
class Finaliser {
 public:
  Finaliser(MapState& state, RegionCarver& carver, VoteMode& votes);

  // Every map.finalise_every_frames frames: finalises the points older than map.finalise_age_frames, or
  // older than map.finalise_min_age_frames and farther than map.finalise_distance_m from the latest camera,
  // and the Steiner vertices no live cube needs; then carves the region around the hole again.
  void Finalise(MapUpdateResult* result);

 private:
  // The live points to finalise, by age (from the front of the arrival queue) and by distance.
  std::vector<std::uint32_t> SelectPoints();
  // The vertices of `finalised` and the Steiner vertices of `released_nodes` (those inserted).
  std::vector<VertexHandle> VerticesToRemove(const std::vector<std::uint32_t>& finalised,
                                             const std::vector<LatticeKey>& released_nodes);
  // update.destroyed = the stars of `removed` (stamped `cell_mark`; the vertices stamped `removing`).
  void CollectStars(const std::vector<VertexHandle>& removed, std::uint32_t removing,
                    std::uint32_t cell_mark);
  // Removes `removed` (and the records of `finalised`), seals the cells refilling the hole with
  // `hole_side`, and freezes `seam`.
  void RemoveAndSeal(const std::vector<VertexHandle>& removed, const std::vector<std::uint32_t>& finalised,
                     const std::vector<VertexHandle>& seam, const HoleSides& hole_side);
  // The region around the refilled hole voted (VoteMode::RevoteReleased) and carved again.
  void RecarveAroundHole(MapUpdateResult* result);

  MapState& state_;
  RegionCarver& carver_;
  VoteMode& votes_;
};

}  // namespace semap::map_internal
