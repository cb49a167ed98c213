#include "engine/map/internal/region_carver.h"

namespace semap::map_internal {

RegionCarver::RegionCarver(MapState& state)
    : state_(state), carver_(&state.dt, state.options.grow_passes, state.options.repair_fill_cost_q()) {}

void RegionCarver::UncarveBoundaryStars(std::vector<CellHandle>* uncarved) {
  // Carve-and-repair keeps the old carved cells and repairs the boundary vertices in Regrow instead: the
  // stars hold several times more cells than the re-triangulated region, and re-carving them was the
  // largest part of an update.
  if (state_.options.extraction == SurfaceExtraction::kGreedyGrowth) {
    carver_.UncarveStars(state_.update.boundary, uncarved);
  }
}

std::size_t RegionCarver::ShrinkNonFree() {
  std::vector<VertexHandle> vertices;
  std::size_t uncarved = 0;
  for (const CellHandle c : state_.update.touched) {
    if (!c->info().carved || c->info().IsFree() || IsPinned(c)) continue;
    c->info().carved = false;
    ++uncarved;
    for (int k = 0; k < 4; ++k) vertices.push_back(c->vertex(k));
  }
  if (state_.options.extraction == SurfaceExtraction::kCarveAndRepair) {
    // Repaired in Regrow, once, with the cells it carves: repairing now, beside the uncarved new cells of
    // the re-triangulated region, would uncarve far around them, only to carve it all again.
    repair_later_ = std::move(vertices);
    return uncarved;
  }
  std::vector<CellHandle> more;
  carver_.Repair(vertices, /*allow_fill=*/false, &more);
  for (const CellHandle c : more) state_.Touch(c);
  return uncarved + more.size();
}

std::size_t RegionCarver::Regrow() {
  std::vector<CellHandle>& changed = state_.update.carve_changed;
  changed.clear();
  if (state_.options.extraction == SurfaceExtraction::kCarveAndRepair) {
    repair_later_.insert(repair_later_.end(), state_.update.boundary.begin(), state_.update.boundary.end());
    const std::size_t carved = carver_.CarveAndRepair(state_.update.touched, &changed, repair_later_);
    repair_later_.clear();
    return carved;
  }
  std::vector<CellHandle> seeds;
  CellHandle best;
  for (const CellHandle c : state_.update.touched) {
    if (c->info().carved || !c->info().IsFree() || state_.dt.is_infinite(c)) continue;
    if (best == CellHandle() || c->info().free_q > best->info().free_q) best = c;
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i)->info().carved) {
        seeds.push_back(c);
        break;
      }
    }
  }
  if (seeds.empty() && best != CellHandle()) seeds.push_back(best);
  return carver_.Grow(seeds, &changed);
}

void RegionCarver::TakeIrregular() { state_.mesher.AddIrregular(carver_.TakeUnrepaired()); }

}  // namespace semap::map_internal
