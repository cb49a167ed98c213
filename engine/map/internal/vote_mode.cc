#include "engine/map/internal/vote_mode.h"

#include "engine/map/internal/depth_vote_mode.h"
#include "engine/map/internal/ray_vote_mode.h"

namespace semap::map_internal {

std::unique_ptr<VoteMode> MakeVoteMode(MapState& state, RegionCarver& carver) {
  if (state.options.visibility == Visibility::kRays) return std::make_unique<RayVoteMode>(state, carver);
  return std::make_unique<DepthVoteMode>(state);
}

EmitRule OutputRule(const MapOptions& options) {
  return {options.drop_steiner_triangles,
          options.visibility == Visibility::kDepth && options.drop_unseen_surface};
}

}  // namespace semap::map_internal
