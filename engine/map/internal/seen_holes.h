// Holes in the seen surface (map.fill_unseen_holes_facets): a few surface facets that no view saw, ringed by
// facets views did see, are taken as seen.
//
// Why: with map.drop_unseen_surface a facet is emitted only once a view saw the point through its centroid
// within ray_extension_m of its plane. A facade mapped from afar has vertices uncertain by decimetres to a
// metre (σ_z = z²σ/(f·B)); a later, closer view sees the true facade, and a facet tilted by its vertices'
// noise misses the tolerance although every facet around it passed. The facade then has single-facet holes
// through which the cameras see whatever was mapped behind it (200 urban frames: strict RMSE vs Velodyne 1.86
// → 3.89 m). A hole ringed by seen facets is such a miss: the views saw a surface all around it. What the
// rule is for — no lids over the street, no ceiling of sky — are large connected regions of unseen facets,
// and stay out.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// A surface facet named from its carved side: the facet of `cell` (carved) opposite its vertex `index`.
struct CarvedFacet {
  CellHandle cell;
  int index = 0;
};

// The surface facet of `c` opposite vertex `i` named from its carved side, when it is a surface facet (one
// side carved) between two finite cells, neither sealed. False otherwise.
bool AsCarvedFacet(const Delaunay& dt, CellHandle c, int i, CarvedFacet* out);

// The surface facet next to `f` across its edge opposite the facet's `e`-th vertex (e in 0..2, the facet's
// vertices in the order of its cell's indices): the first facet met walking around that edge from f's cell
// through carved cells (the other side of f's carved wedge). False where the walk meets a sealed or infinite
// cell.
bool SurfaceNeighbour(const Delaunay& dt, const CarvedFacet& f, int e, CarvedFacet* out);

// Marks seen (MarkFacetSeen) every hole met from the surface facets of `cells` and their edge-neighbours: a
// set of unseen surface facets, connected across edges, of at most `max_facets` facets, whose every other
// edge-neighbour is seen. A hole with a frozen or Steiner vertex (a seam's seen bits are final; Steiner
// triangles are never output), or next to a sealed or infinite cell, is left alone. The result does not
// depend on the order of `cells`. Returns the number of facets marked.
std::size_t FillUnseenHoles(Delaunay* dt, const std::vector<CellHandle>& cells, int max_facets);

}  // namespace semap::map_internal
