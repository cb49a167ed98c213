#include "engine/map/internal/finaliser.h"

namespace semap::map_internal {

Finaliser::Finaliser(MapState& state, RegionCarver& carver, VoteMode& votes)
    : state_(state), carver_(carver), votes_(votes) {}

void Finaliser::Finalise(MapUpdateResult* result) {
  const MapOptions& options = state_.options;
  const int max_age = options.finalise_age_frames;
  if ((max_age <= 0 && options.finalise_distance_m <= 0.0) ||
      state_.frame % options.finalise_every_frames != 0) {
    return;
  }
  const std::vector<std::uint32_t> finalised = SelectPoints();
  std::vector<LatticeKey> released_nodes;
  if (max_age > 0) state_.lattice.Expire(state_.frame - max_age, &released_nodes);
  if (finalised.empty() && released_nodes.empty()) return;
  const std::vector<VertexHandle> removed = VerticesToRemove(finalised, released_nodes);

  // The stars of the removed vertices are destroyed.
  const std::uint32_t removing = state_.NewMark();
  const std::uint32_t cell_mark = state_.NewMark();
  CollectStars(removed, removing, cell_mark);
  state_.CollectBoundary(removing);
  // The seam: the staying vertices of the surface facets the change touches (emitted, or kept by a sealed
  // cell), and of the hole's boundary facets with carved space behind (a sealed cell keeps it carved across
  // them). Only their cells must never change again; the rest of the hole's boundary stays free.
  const std::vector<VertexHandle> seam =
      HoleSeam(state_.dt, state_.update.destroyed, cell_mark, removing, state_.NewMark());
  state_.mesher.EmitHole(state_.update.destroyed, cell_mark, removed, seam);
  // The carving seen across each facet of the hole's boundary, from inside the hole: the cells that will
  // fill the hole keep it (SealHole).
  const HoleSides hole_side = RecordHoleSides(state_.update.destroyed, cell_mark);
  votes_.ReleaseVotes(finalised, cell_mark);
  RemoveAndSeal(removed, finalised, seam, hole_side);
  result->points_finalised = finalised.size();
  result->vertices_removed = removed.size();
  RecarveAroundHole(result);
}

std::vector<std::uint32_t> Finaliser::SelectPoints() {
  const int max_age = state_.options.finalise_age_frames;
  const double max_distance = state_.options.finalise_distance_m;
  // By age: from the front of the queue, which is in last-seen order. By distance: any point old enough and
  // too far from the latest camera, wherever it stands in the queue (the queue is not in distance order:
  // stopping at the first near point kept the whole map live behind it).
  std::vector<std::uint32_t> finalised;
  std::deque<Arrival>& arrival = state_.arrival;
  while (!arrival.empty()) {
    const Arrival a = arrival.front();
    const auto it = state_.points.find(a.id);
    if (it == state_.points.end() || it->second.last_seen != a.frame) {
      arrival.pop_front();  // stale: seen again since (a later entry stands for it), or gone
      continue;
    }
    if (!(max_age > 0 && state_.frame - it->second.last_seen > max_age)) break;
    finalised.push_back(a.id);
    arrival.pop_front();
  }
  if (max_distance <= 0.0) return finalised;
  for (const Arrival& a : arrival) {
    const auto it = state_.points.find(a.id);
    if (it == state_.points.end() || it->second.last_seen != a.frame) continue;  // stale
    const PointRecord& p = it->second;
    if (state_.frame - p.last_seen >= state_.options.finalise_min_age_frames &&
        (p.position - state_.last_camera).norm() > max_distance) {
      finalised.push_back(a.id);  // its entry turns stale once the point is erased
    }
  }
  return finalised;
}

std::vector<VertexHandle> Finaliser::VerticesToRemove(const std::vector<std::uint32_t>& finalised,
                                                      const std::vector<LatticeKey>& released_nodes) {
  std::vector<VertexHandle> removed;
  for (std::uint32_t id : finalised) removed.push_back(state_.points.at(id).vertex);
  for (LatticeKey node : released_nodes) {
    auto it = state_.steiner.find(node);
    if (it == state_.steiner.end()) continue;  // never inserted: it would have cut into a seam
    removed.push_back(it->second);
    state_.steiner.erase(it);
  }
  return removed;
}

void Finaliser::CollectStars(const std::vector<VertexHandle>& removed, std::uint32_t removing,
                             std::uint32_t cell_mark) {
  std::vector<CellHandle>& destroyed = state_.update.destroyed;
  destroyed.clear();
  std::vector<CellHandle> star;
  for (const VertexHandle v : removed) {
    v->info().stamp = removing;
    star.clear();
    state_.dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == cell_mark) continue;
      c->info().stamp = cell_mark;
      destroyed.push_back(c);
    }
  }
}

void Finaliser::RemoveAndSeal(const std::vector<VertexHandle>& removed,
                              const std::vector<std::uint32_t>& finalised,
                              const std::vector<VertexHandle>& seam, const HoleSides& hole_side) {
  // The cells filling the holes are those around the boundary vertices not there before.
  const std::uint32_t old_mark = state_.StampCellsAround(state_.update.boundary);
  // One hole per connected cluster of removed vertices, re-triangulated once: the same Delaunay result as
  // removing them one by one, about 2.5 times faster on the ~30,000 vertices of a finalisation.
  carver_.TakeIrregular();
  state_.mesher.ForgetIrregular(removed);
  state_.dt.remove_cluster(removed.begin(), removed.end());
  for (std::uint32_t id : finalised) state_.points.erase(id);
  state_.update.created_mark = state_.NewMark();
  state_.MarkCreatedCells(state_.update.boundary, old_mark);
  // Removing nearly everything can leave a flat or empty triangulation: no cells to seal then.
  if (state_.dt.dimension() == 3) {
    SealHole(&state_.dt, state_.update.boundary, state_.update.created_mark, hole_side);
  }
  // The seam's fans, part emitted and part live, stay whole: every cell around them keeps its carving.
  for (const VertexHandle v : seam) v->info().frozen = true;
}

void Finaliser::RecarveAroundHole(MapUpdateResult* result) {
  state_.BeginTouched();
  std::vector<CellHandle> uncarved;
  carver_.UncarveBoundaryStars(&uncarved);
  for (const CellHandle c : uncarved) state_.Touch(c);
  votes_.RevoteReleased(result);
  result->cells_uncarved += uncarved.size() + carver_.ShrinkNonFree();
  result->cells_carved += carver_.Regrow();
}

}  // namespace semap::map_internal
