// Reads the surface (boundary of the carved region) and the per-cell votes out of the triangulation.
#pragma once

#include <vector>

#include "engine/core/mesh.h"
#include "engine/core/mesh_delta.h"
#include "engine/map/internal/triangulation.h"
#include "engine/map/map_types.h"

namespace semap::map_internal {

// A facet's identity: the sorted keys of its vertices.
using FacetKey = std::array<std::uint64_t, 3>;

// The stable key of a vertex: its point id, or (bit 63 set) a Steiner vertex number.
inline std::uint64_t VertexKey(VertexHandle v) {
  return v->info().steiner ? (std::uint64_t(1) << 63) | v->info().id : v->info().id;
}

// One boundary facet, oriented counter-clockwise seen from the carved (free) side.
struct SurfaceFacet {
  std::array<VertexHandle, 3> vertices;
  FacetKey id;  // sorted vertex keys
};

// The facet of `carved_cell` opposite its vertex `opposite`, oriented counter-clockwise seen from the cell.
SurfaceFacet OrientedFacet(CellHandle carved_cell, int opposite);

// Boundary facets between carved and uncarved cells; with `drop_steiner`, facets touching a Steiner vertex
// are left out. Appends to `facets`.
void CollectSurface(const Delaunay& dt, bool drop_steiner, std::vector<SurfaceFacet>* facets);

// Builds a mesh of `facets` (vertices shared, with their info().attributes; Steiner vertices labelled
// `unlabelled`, grey), with the vertex keys as stable vertex ids.
IdentifiedMesh FacetsToMesh(const std::vector<SurfaceFacet>& facets, Label unlabelled);

// Votes of every finite cell.
std::vector<CellVotes> CollectCellVotes(const Delaunay& dt);

// Finite cells that are carved / free.
std::size_t CountCarvedCells(const Delaunay& dt);
std::size_t CountFreeCells(const Delaunay& dt);

}  // namespace semap::map_internal
