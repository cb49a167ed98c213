// Reads the surface (boundary of the carved region) and the per-cell votes out of the triangulation.
#pragma once

#include <unordered_map>
#include <vector>

#include "engine/core/mesh.h"
#include "engine/core/mesh_delta.h"
#include "engine/map/internal/triangulation.h"
#include "engine/map/map_types.h"

namespace semap::map_internal {

// A facet's identity: the sorted keys of its vertices.
using FacetKey = std::array<std::uint64_t, 3>;
struct FacetKeyHash {
  std::size_t operator()(const FacetKey& t) const {
    std::size_t h = 0;
    for (auto k : t) h = h * 0x9E3779B97F4A7C15ull + std::hash<std::uint64_t>()(k);
    return h;
  }
};

// The stable key of a vertex: its point id, or (bit 63 set) a Steiner vertex number.
inline std::uint64_t VertexKey(VertexHandle v) {
  return v->info().steiner ? (std::uint64_t(1) << 63) | v->info().id : v->info().id;
}

// The key of copy `copy` of the vertex keyed `vertex_key` (copy 0 is the vertex itself).
inline std::uint64_t CopyKey(std::uint64_t vertex_key, std::uint8_t copy) {
  return vertex_key | (std::uint64_t(copy) << 32);
}

// The id under which the output names copy `copy` of vertex `v`: its CopyKey, with the vertex's output
// version (VertexInfo::output_version) above, so that a vertex the output moved comes back under a new id.
inline std::uint64_t OutputKey(VertexHandle v, std::uint8_t copy) {
  constexpr int kVersionShift = 40;  // above the copy's 8 bits at 32, below the Steiner bit at 63
  return CopyKey(VertexKey(v), copy) | (std::uint64_t(v->info().output_version) << kVersionShift);
}

// One boundary facet, oriented counter-clockwise seen from the carved (free) side.
struct SurfaceFacet {
  std::array<VertexHandle, 3> vertices;
  FacetKey id;  // sorted vertex keys
  // The copy of each vertex this facet uses (see AssignCopies): 0 but at pinched vertices.
  std::array<std::uint8_t, 3> copy{0, 0, 0};
  // No view saw it as a surface (CellInfo::seen_facets on either side; a facet on a seam of finalisation
  // keeps the bit of its live side).
  bool unseen = false;
};

// Which surface facets the output leaves out.
struct EmitRule {
  bool drop_steiner = true;  // those touching a Steiner vertex
  bool drop_unseen = false;  // those no view saw as a surface (SurfaceFacet::unseen)
};

// Pinched vertices. The whole surface (the boundary of the carved cells) is a closed 2-manifold: around each
// vertex its facets form one cycle. The output leaves facets out (those touching a Steiner vertex), which can
// cut a vertex's cycle into several runs that meet only at the vertex: a pinch. Each run gets its own copy
// of the vertex (same position and attributes, its own key), so every output vertex has a single fan.
//
// FanCopies: the copies fixed at a seam of finalisation, where part of a vertex's cycle was emitted as
// finalised triangles and the rest stays live (and pinned): per facet (by id), the copy of the vertex in
// each slot of the id (kUnassigned where the vertex is not frozen).
using FanCopies = std::unordered_map<FacetKey, std::array<std::uint8_t, 3>, FacetKeyHash>;
inline constexpr std::uint8_t kUnassigned = 0xFF;

// Numbers the runs of `fan` (the emitted facets around `v`, not frozen): two facets sharing an edge (v, w)
// are one run when they bound the same carved wedge around the edge (one wedge at a regular vertex; a
// vertex the carver could not make regular may have several). Runs are ordered by their smallest facet id
// and the first keeps copy 0. Returns each facet's copy. With `regular` (v and its neighbours on the surface
// are regular: each surface edge bounds one carved wedge), two facets sharing an edge are one run without
// walking the cells around it.
std::vector<std::uint8_t> FanRuns(const Delaunay& dt, VertexHandle v,
                                  const std::vector<const SurfaceFacet*>& fan, bool regular);

// Sets SurfaceFacet::copy: at the vertices of `open` (those of facets left out: they can pinch) and of
// `irregular` (vertices the carver could not make regular, beside a seam, and their neighbours) from their
// runs in `facets`, and at frozen vertices from `frozen` (may be null without them).
void AssignCopies(const Delaunay& dt, std::vector<SurfaceFacet>* facets,
                  const std::vector<VertexHandle>& open, const std::vector<VertexHandle>& irregular,
                  const FanCopies* frozen);

// Whether the output leaves `f` out.
bool LeftOut(const SurfaceFacet& f, const EmitRule& rule);

// The facet of `carved_cell` opposite its vertex `opposite`, oriented counter-clockwise seen from the cell.
SurfaceFacet OrientedFacet(CellHandle carved_cell, int opposite);

// Whether the neighbour of `c` across its facet `i` counts as carved seen across that facet.
inline bool NeighbourCarved(CellHandle c, int i) {
  const CellHandle n = c->neighbor(i);
  return n->info().IsSealed() ? n->info().CarvedAcross(n->index(c)) : n->info().carved;
}

// Whether the facet of finite `c` opposite vertex `i` is a surface facet to be taken from `c`, so that each
// is taken once: from its carved side, or from its finite side when the carved side is infinite (possible
// beside a sealed hole at the hull; OrientedSurfaceFacet flips it).
inline bool TakenFrom(const Delaunay& dt, CellHandle c, int i) {
  const bool carved_here = c->info().CarvedAcross(i);
  if (!carved_here && !dt.is_infinite(c->neighbor(i))) return false;  // taken from the finite carved side
  return carved_here != NeighbourCarved(c, i);
}

// The surface facet of finite `c` opposite vertex `i` (carved on exactly one side; the infinite vertex not in
// it), oriented counter-clockwise seen from the carved side.
SurfaceFacet OrientedSurfaceFacet(CellHandle c, int i);

// Boundary facets between carved and uncarved cells (sealed cells count as carved across the facets their
// bits say); those `rule` leaves out are not appended, and their vertices go to `open` (may be null): they
// can pinch. Appends to `facets`.
void CollectSurface(const Delaunay& dt, const EmitRule& rule, std::vector<SurfaceFacet>* facets,
                    std::vector<VertexHandle>* open = nullptr);

// The surface facets through finite vertex `v`, each once, oriented.
void SurfaceAround(const Delaunay& dt, VertexHandle v, std::vector<SurfaceFacet>* facets);

// Builds a mesh of `facets` (vertices shared, with their info().attributes; Steiner vertices labelled
// `unlabelled`, grey), with the vertex keys as stable vertex ids (CopyKey for the copies of pinched
// vertices).
// Where the output puts a vertex (empty: where the triangulation has it).
using VertexPosition = std::function<Eigen::Vector3d(VertexHandle)>;
inline Eigen::Vector3d PositionOf(const VertexPosition& position, VertexHandle v) {
  return position ? position(v) : ToEigen(v->point());
}
IdentifiedMesh FacetsToMesh(const std::vector<SurfaceFacet>& facets, Label unlabelled,
                            const VertexPosition& position = {});

// The output surface: CollectSurface, AssignCopies (with `frozen`, may be null), FacetsToMesh.
IdentifiedMesh ExtractSurfaceMesh(const Delaunay& dt, const EmitRule& rule,
                                  const std::vector<VertexHandle>& irregular, const FanCopies* frozen,
                                  Label unlabelled, const VertexPosition& position = {});

// Votes of every finite cell.
std::vector<CellVotes> CollectCellVotes(const Delaunay& dt);

// Finite cells that are carved / free.
std::size_t CountCarvedCells(const Delaunay& dt);
std::size_t CountFreeCells(const Delaunay& dt);

}  // namespace semap::map_internal
