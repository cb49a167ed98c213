#include "engine/map/internal/hole_cut.h"

#include "engine/core/check.h"
#include "engine/map/internal/surface_extraction.h"

namespace semap::map_internal {

std::vector<VertexHandle> HoleSeam(const Delaunay& dt, const std::vector<CellHandle>& destroyed,
                                   std::uint32_t destroyed_mark, std::uint32_t removed_mark,
                                   std::uint32_t seam_mark) {
  std::vector<VertexHandle> seam;
  for (const CellHandle d : destroyed) {
    for (int i = 0; i < 4; ++i) {
      // A surface facet, or a boundary facet the hole is carved behind (a sealed cell will keep that).
      const bool surface = d->info().CarvedAcross(i) != NeighbourCarved(d, i);
      const bool carved_behind = d->neighbor(i)->info().stamp != destroyed_mark && d->info().CarvedAcross(i);
      if (!surface && !carved_behind) continue;
      for (int k = 0; k < 4; ++k) {
        const VertexHandle v = d->vertex(k);
        if (k == i || dt.is_infinite(v) || v->info().stamp == removed_mark || v->info().stamp == seam_mark)
          continue;
        v->info().stamp = seam_mark;
        seam.push_back(v);
      }
    }
  }
  return seam;
}

HoleSides RecordHoleSides(const std::vector<CellHandle>& destroyed, std::uint32_t destroyed_mark) {
  HoleSides sides;
  for (const CellHandle d : destroyed) {
    for (int i = 0; i < 4; ++i) {
      if (d->neighbor(i)->info().stamp == destroyed_mark) continue;
      sides[SortedFacet(d, i)] = {d->info().CarvedAcross(i), FacetSeen(d, i)};
    }
  }
  return sides;
}

void SealHole(Delaunay* dt, const std::vector<VertexHandle>& boundary, std::uint32_t created_mark,
              const HoleSides& sides) {
  std::vector<CellHandle> star;
  for (const VertexHandle v : boundary) {
    star.clear();
    dt->incident_cells(v, std::back_inserter(star));
    for (const CellHandle h : star) {
      if (h->info().created != created_mark || h->info().IsSealed()) continue;
      std::uint8_t sealed = CellInfo::kSealed;
      for (int i = 0; i < 4; ++i) {
        if (h->neighbor(i)->info().created == created_mark) continue;  // inside the hole: no surface
        const auto it = sides.find(SortedFacet(h, i));
        SEMAP_ASSERT(it != sides.end(), "a facet of the refilled hole was not on the hole's boundary");
        if (it->second.carved) sealed |= std::uint8_t(1u << i);
        if (it->second.seen) MarkFacetSeen(h, i);
      }
      h->info().sealed = sealed;
      h->info().carved = false;
    }
  }
}

}  // namespace semap::map_internal
