// Memory bound of the incremental map: finalising and releasing the parts far behind the camera.
#include "engine/core/check.h"
#include "engine/map/internal/incremental_state.h"

namespace semap::map_internal {

void IncrementalState::Finalise(MapUpdateResult* result) {
  const int max_age = options_.finalise_age_frames;
  const double max_distance = options_.finalise_distance_m;
  if ((max_age <= 0 && max_distance <= 0.0) || frame_ % options_.finalise_every_frames != 0) return;

  // Points to finalise: the oldest first (the distance test is made on the oldest points only, in order).
  std::vector<std::uint32_t> finalised;
  while (!arrival_.empty()) {
    const PointRecord& p = points_.at(arrival_.front());
    const std::int64_t age = frame_ - p.frame;
    const bool too_old = max_age > 0 && age > max_age;
    const bool too_far = max_distance > 0.0 && age >= options_.finalise_min_age_frames &&
                         (p.position - last_camera_).norm() > max_distance;
    if (!too_old && !too_far) break;
    finalised.push_back(arrival_.front());
    arrival_.pop_front();
  }
  std::vector<LatticeKey> released_nodes;
  if (max_age > 0) lattice_.Expire(frame_ - max_age, &released_nodes);
  if (finalised.empty() && released_nodes.empty()) return;

  std::vector<VertexHandle> removed;
  for (std::uint32_t id : finalised) removed.push_back(points_.at(id).vertex);
  EmitFinalisedFacets(removed);
  for (LatticeKey node : released_nodes) {
    auto it = steiner_.find(node);
    SEMAP_ASSERT(it != steiner_.end());
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
  const std::uint32_t old_mark = NewMark();
  std::vector<CellHandle> around;
  for (const VertexHandle v : boundary_) {
    around.clear();
    dt_.incident_cells(v, std::back_inserter(around));
    for (const CellHandle c : around) c->info().stamp = old_mark;
  }
  // One hole per connected cluster of removed vertices, re-triangulated once: the same Delaunay result as
  // removing them one by one, about 2.5 times faster on the ~30,000 vertices of a finalisation.
  dt_.remove_cluster(removed.begin(), removed.end());
  for (std::uint32_t id : finalised) points_.erase(id);
  created_mark_ = NewMark();
  MarkCreatedCells(boundary_, old_mark);
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

void IncrementalState::EmitFinalisedFacets(const std::vector<VertexHandle>& vertices) {
  std::unordered_set<FacetKey, FacetKeyHash> emitted;
  std::vector<CellHandle> star;
  for (const VertexHandle v : vertices) {
    star.clear();
    dt_.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (!c->info().carved) continue;
      for (int i = 0; i < 4; ++i) {
        if (c->vertex(i) == v || c->neighbor(i)->info().carved) continue;
        const SurfaceFacet f = OrientedFacet(c, i);
        bool has_steiner = false;
        for (const VertexHandle u : f.vertices) has_steiner |= u->info().steiner;
        if ((has_steiner && options_.drop_steiner_triangles) || !emitted.insert(f.id).second) continue;
        std::array<std::uint32_t, 3> tri;
        for (int k = 0; k < 3; ++k) {
          const VertexHandle u = f.vertices[k];
          auto [it, inserted] =
              finalised_index_.try_emplace(VertexKey(u), std::uint32_t(finalised_.mesh.vertices.size()));
          if (inserted) {
            finalised_.mesh.vertices.push_back(ToEigen(u->point()));
            finalised_.vertex_ids.push_back(VertexKey(u));
            const PointAttributes& a = u->info().attributes;  // the defaults for a Steiner vertex
            finalised_.mesh.labels.push_back(a.label);
            finalised_.mesh.colors_rgb.push_back(a.color_rgb);
          }
          tri[k] = it->second;
        }
        finalised_.mesh.triangles.push_back(tri);
      }
    }
  }
}

}  // namespace semap::map_internal
