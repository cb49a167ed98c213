// The carving of the region an update changed: the cells whose votes or neighbours changed (MapState's
// update.touched, update.boundary) carved or uncarved by their votes, and the manifold made whole again
// around them.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/map/internal/manifold_carver.h"
#include "engine/map/internal/map_state.h"

namespace semap::map_internal {

// Works on the MapState it is made with; owns the ManifoldCarver. Not thread-safe.
class RegionCarver {
 public:
  explicit RegionCarver(MapState& state);

  // The greedy growth restarts around a re-triangulated region: uncarves the stars of update.boundary
  // (appended to `uncarved`). Carve-and-repair does not need it.
  void UncarveBoundaryStars(std::vector<CellHandle>* uncarved);
  // Uncarves the touched cells that are no longer free, then repairs the manifold around them (greedy
  // growth; carve-and-repair leaves their vertices to Regrow's repair). Returns the cells uncarved.
  std::size_t ShrinkNonFree();
  // Carves the free cells of update.touched and makes the manifold whole again around them and
  // update.boundary; lists in update.carve_changed the cells whose carving that changed beyond the touched
  // ones. Returns the cells carved.
  std::size_t Regrow();
  // Hands the vertices the carver could not repair to the mesher.
  void TakeIrregular();

 private:
  MapState& state_;
  ManifoldCarver carver_;
  std::vector<VertexHandle> repair_later_;  // vertices ShrinkNonFree leaves to Regrow's repair
};

}  // namespace semap::map_internal
