// The batch Delaunay map: the reference the incremental map is checked against.
#pragma once

#include <vector>

#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh.h"
#include "engine/map/map_options.h"
#include "engine/map/map_types.h"

namespace semap {

struct BatchMapResult {
  Mesh mesh;  // the manifold surface (Steiner triangles dropped if the options say so)
  std::vector<CellVotes> cell_votes;  // filled when requested
  MapStatistics statistics;
};

// Builds the map of `cloud` in one go: Delaunay triangulation of the points and the Steiner lattice
// (spatially sorted batch insertion), one ray from each point's first camera (cloud.camera_index) plus one
// per extra observation, votes, and region growing from the cell with the highest free vote. Points beyond
// options.max_ray_length_m from their first camera are left out, with their rays. Points at the same position
// share one vertex (and its rays). Requires cloud.camera_index and at least one camera.
// `with_cell_votes`: also return every cell's votes (for tests; costs memory).
BatchMapResult BuildBatchMap(const MapOptions& options, const LabelledCloud& cloud,
                             const std::vector<Observation>& extra_observations,
                             bool with_cell_votes = false);

}  // namespace semap
