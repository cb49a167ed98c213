// Walks a visibility ray through the triangulation and computes its votes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/map/internal/triangulation.h"
#include "engine/map/map_options.h"

namespace semap::map_internal {

// The cells one ray votes on, with their fixed-point weights.
struct RayVotes {
  struct Entry {
    CellHandle cell;
    std::int64_t weight_q = 0;
    bool matter = false;  // true: behind the point (matter vote); false: between camera and point (free vote)
  };
  std::vector<Entry> entries;
};

// The paper's ray geometry, as MapOptions sets it (the defaults are declared there only).
struct RayGeometry {
  explicit RayGeometry(const MapOptions& options)
      : sigma_free_m(options.sigma_free_m),
        sigma_matter_m(options.sigma_matter_m),
        extension_m(options.ray_extension_m()) {}
  double sigma_free_m;
  double sigma_matter_m;
  double extension_m;  // MapOptions::ray_extension_m()
};

// Where along a ray the cells it must vote on lie: distances from the camera, projected on the ray.
struct RaySpan {
  double from_m = 0.0;
  double to_m = 0.0;
};

// Fills `votes` with the finite cells whose interior the segment target → camera crosses (free votes) and
// those crossed by the extension of camera → target behind the target by `extension_m` (matter votes).
// The walk uses CGAL's segment traverser: exact orientation predicates, facet by facet; when the segment goes
// through an edge or a vertex it continues in the cell entered strictly, and it always ends (the segment is
// finite and each step advances along it). Returns false (and no votes) for a degenerate ray (camera at the
// point). Requires dimension 3 and the camera and the extension end inside the convex hull.
// With `only_created` ≠ 0, only the cells whose info().created equals it get an entry (the others are walked
// through without computing their weight). With `span` as well, every such cell must lie within it along
// the ray; each walk stops at the first cell wholly past it (all four vertices), so a retraced ray walks the
// changed region and what lies between it and the point, not all the way to the camera.
bool ComputeRayVotes(const Delaunay& dt, VertexHandle target, const Eigen::Vector3d& camera,
                     const RayGeometry& geometry, RayVotes* votes, std::uint32_t only_created = 0,
                     const RaySpan* span = nullptr);

}  // namespace semap::map_internal
