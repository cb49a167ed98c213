// Value types shared by the batch and the incremental Delaunay maps.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/mesh.h"

namespace semap {

// An extra observation of a point by a camera (a ray camera → point), besides the point's first camera.
struct Observation {
  std::uint32_t point = 0;   // point index (batch: into the cloud; incremental: a point id given by Update)
  std::uint32_t camera = 0;  // camera index into the cloud's camera_centers_world
};

// Votes are accumulated in fixed point: kVoteFixedScale units per unit weight, so that sums are exact.
inline constexpr double kVoteFixedScale = double(1 << 24);

// The votes of one finite cell, identified by its four vertex positions in lexicographic order.
struct CellVotes {
  std::array<Eigen::Vector3d, 4> vertices;
  std::int64_t free_fixed = 0;
  std::int64_t matter_fixed = 0;
  bool carved = false;  // inside the extracted free-space region
  bool sealed =
      false;  // refills a finalised region (incremental map): its carving is fixed, its votes unused
};

// Sizes and work counters of a map.
struct MapStatistics {
  std::size_t num_points = 0;  // live data vertices
  std::size_t num_steiner_vertices = 0;
  std::size_t num_cells = 0;  // finite cells
  std::size_t num_carved_cells = 0;
  std::size_t num_free_cells = 0;   // cells with free > matter (carved or not)
  std::size_t num_rays = 0;         // live rays
  std::uint64_t rays_traced = 0;    // walks done so far (traces and untraces)
  std::uint64_t cells_visited = 0;  // cells visited by those walks
  // map.fill_unseen_holes_facets: unseen surface facets taken as seen so far (small holes ringed by seen
  // ones).
  std::uint64_t facets_taken_as_seen = 0;
  // map.fuse_gate_sigmas: vertices moved to their fused estimate, and outliers removed, so far.
  std::uint64_t vertices_moved = 0;
  std::uint64_t vertices_outliers = 0;
};

}  // namespace semap
