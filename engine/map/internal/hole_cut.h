// The finaliser's cut: the vertices finalisation releases leave the triangulation without changing the
// surface that stays live. The cells that refill their hole are sealed: never carved, each carries across its
// facets on the hole's boundary the carving (and seen state) of the released cell that was behind it; and the
// seam's vertices freeze, so that the cells around them keep their carving for good.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// What a released cell leaves across one facet of the hole's boundary to the cell that refills it.
struct HoleSide {
  bool carved = false;  // the released cell counted as carved across the facet
  bool seen = false;    // the facet was seen as a surface (CellInfo::seen_facets)
};
using HoleSides = std::unordered_map<FacetHandles, HoleSide, FacetHandlesHash>;

// The seam of a cut: the staying vertices (not stamped `removed_mark`) of the facets of `destroyed` (the
// cells the removal destroys, stamped `destroyed_mark`) that are surface facets (emitted, or kept by a sealed
// cell) or boundary facets of the hole with carved space behind it (a sealed cell keeps it carved across
// them). Only their cells must never change again; the rest of the hole's boundary stays free. Stamps the
// seam's vertices `seam_mark`.
std::vector<VertexHandle> HoleSeam(const Delaunay& dt, const std::vector<CellHandle>& destroyed,
                                   std::uint32_t destroyed_mark, std::uint32_t removed_mark,
                                   std::uint32_t seam_mark);

// The carving and seen state of `destroyed`'s cells across each facet of the hole's boundary (towards a cell
// not stamped `destroyed_mark`), by the facet's vertices.
HoleSides RecordHoleSides(const std::vector<CellHandle>& destroyed, std::uint32_t destroyed_mark);

// Seals the cells refilling the hole (around `boundary`, marked `created_mark` in CellInfo::created, not
// sealed yet) with `sides`: each facet towards a cell not created now must be in `sides`.
void SealHole(Delaunay* dt, const std::vector<VertexHandle>& boundary, std::uint32_t created_mark,
              const HoleSides& sides);

}  // namespace semap::map_internal
