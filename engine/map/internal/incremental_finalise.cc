// Memory bound of the incremental map: finalising and releasing the parts far behind the camera.
#include "engine/core/check.h"
#include "engine/map/internal/incremental_state.h"

namespace semap::map_internal {

void IncrementalState::Finalise(MapUpdateResult* result) {
  const int max_age = options_.finalise_age_frames;
  const double max_distance = options_.finalise_distance_m;
  if ((max_age <= 0 && max_distance <= 0.0) || frame_ % options_.finalise_every_frames != 0) return;

  // Points to finalise. By age: from the front of the queue, which is in last-seen order. By distance: any
  // point old enough and too far from the latest camera, wherever it stands in the queue (the queue is not
  // in distance order: stopping at the first near point kept the whole map live behind it).
  std::vector<std::uint32_t> finalised;
  while (!arrival_.empty()) {
    const Arrival a = arrival_.front();
    const auto it = points_.find(a.id);
    if (it == points_.end() || it->second.last_seen != a.frame) {
      arrival_.pop_front();  // stale: seen again since (a later entry stands for it), or gone
      continue;
    }
    if (!(max_age > 0 && frame_ - it->second.last_seen > max_age)) break;
    finalised.push_back(a.id);
    arrival_.pop_front();
  }
  if (max_distance > 0.0) {
    for (const Arrival& a : arrival_) {
      const auto it = points_.find(a.id);
      if (it == points_.end() || it->second.last_seen != a.frame) continue;  // stale
      const PointRecord& p = it->second;
      if (frame_ - p.last_seen >= options_.finalise_min_age_frames &&
          (p.position - last_camera_).norm() > max_distance) {
        finalised.push_back(a.id);  // its entry turns stale once the point is erased below
      }
    }
  }
  std::vector<LatticeKey> released_nodes;
  if (max_age > 0) lattice_.Expire(frame_ - max_age, &released_nodes);
  if (finalised.empty() && released_nodes.empty()) return;

  std::vector<VertexHandle> removed;
  for (std::uint32_t id : finalised) removed.push_back(points_.at(id).vertex);
  for (LatticeKey node : released_nodes) {
    auto it = steiner_.find(node);
    if (it == steiner_.end())
      continue;  // never inserted: it would have cut into a seam (see DropPinnedConflicts)
    removed.push_back(it->second);
    steiner_.erase(it);
  }

  // The stars of the removed vertices are destroyed: untrace the rays through them and those of the
  // finalised points (which may cross cells elsewhere).
  const std::uint32_t removing = NewMark();
  const std::uint32_t cell_mark = NewMark();
  destroyed_.clear();
  std::vector<CellHandle> star;
  for (const VertexHandle v : removed) {
    v->info().stamp = removing;
    star.clear();
    dt_.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == cell_mark) continue;
      c->info().stamp = cell_mark;
      destroyed_.push_back(c);
    }
  }
  CollectBoundary(removing);
  // The seam: the staying vertices of the surface facets the change touches (emitted, or kept by a sealed
  // cell), and of the hole's boundary facets with carved space behind (a sealed cell keeps it carved across
  // them). Only their cells must never change again; the rest of the hole's boundary stays free.
  const std::vector<VertexHandle> seam = HoleSeam(dt_, destroyed_, cell_mark, removing, NewMark());
  mesher_.EmitHole(destroyed_, cell_mark, removed, seam);
  // The carving seen across each facet of the hole's boundary, from inside the hole: the cells that will
  // fill the hole keep it (SealHole).
  const HoleSides hole_side = RecordHoleSides(destroyed_, cell_mark);
  std::vector<std::uint32_t> affected;
  CollectAffectedRays(&affected);
  // The finalised points' rays are untraced in full (they may cross cells far from the removed stars).
  decreased_.clear();
  std::vector<std::uint32_t> released;
  for (std::uint32_t id : finalised) {
    const auto& rays = points_.at(id).rays;
    released.insert(released.end(), rays.begin(), rays.end());
  }
  TraceRays(released, -1);
  for (std::uint32_t ray : released) {
    auto cam = cameras_.find(rays_[ray].camera);
    if (--cam->second.live_rays == 0 && cam->second.frame < frame_) cameras_.erase(cam);
    rays_.Release(ray);
  }
  std::vector<CellHandle> lost;  // surviving cells that lost votes
  for (const CellHandle c : decreased_) {
    if (c->info().stamp != cell_mark) lost.push_back(c);
  }
  std::vector<std::uint32_t> retrace;
  for (std::uint32_t ray : affected) {
    if (rays_[ray].live) retrace.push_back(ray);
  }

  // Remove; the cells filling the holes are those around the boundary vertices not there before.
  const std::uint32_t old_mark = StampCellsAround(boundary_);
  // One hole per connected cluster of removed vertices, re-triangulated once: the same Delaunay result as
  // removing them one by one, about 2.5 times faster on the ~30,000 vertices of a finalisation.
  TakeIrregular();
  mesher_.ForgetIrregular(removed);
  dt_.remove_cluster(removed.begin(), removed.end());
  for (std::uint32_t id : finalised) points_.erase(id);
  created_mark_ = NewMark();
  MarkCreatedCells(boundary_, old_mark);
  // Removing nearly everything can leave a flat or empty triangulation: no cells to seal then.
  if (dt_.dimension() == 3) SealHole(&dt_, boundary_, created_mark_, hole_side);
  // The seam's fans, part emitted and part live, stay whole: every cell around them keeps its carving.
  for (const VertexHandle v : seam) v->info().frozen = true;
  result->points_finalised = finalised.size();
  result->vertices_removed = removed.size();

  touched_.clear();
  touch_mark_ = NewMark();
  std::vector<CellHandle> uncarved;
  UncarveBoundaryStars(&uncarved);
  uncarved.insert(uncarved.end(), lost.begin(), lost.end());
  for (const CellHandle c : uncarved) {
    if (c->info().stamp == touch_mark_) continue;
    c->info().stamp = touch_mark_;
    touched_.push_back(c);
  }
  TraceRays(retrace, +1, /*only_created=*/true);
  result->rays_retraced += retrace.size();
  result->cells_uncarved += uncarved.size() - lost.size() + ShrinkNonFree();
  result->cells_carved += Regrow();
}

}  // namespace semap::map_internal
