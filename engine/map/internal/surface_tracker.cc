#include "engine/map/internal/surface_tracker.h"

#include <algorithm>

#include "engine/core/check.h"

namespace semap::map_internal {

std::size_t SurfaceTracker::KeyHash::operator()(const Key& k) const {
  std::size_t h = 0;
  for (auto v : k) h = h * 0x9E3779B97F4A7C15ull + std::hash<std::uint64_t>()(v);
  return h;
}

void SurfaceTracker::Sync() {
  // Created cells first, with the old cells' surface_carved flags as they were: a facet a created cell
  // shares with an old cell may have to enter the surface (or leave it) although no carved flag moved.
  const std::uint32_t created_mark = ++mark_;
  unique_.clear();
  for (const CellHandle c : created_) {
    if (c->info().surface_mark == created_mark) continue;
    c->info().surface_mark = created_mark;
    unique_.push_back(c);
  }
  for (const CellHandle c : unique_) {
    for (int i = 0; i < 4; ++i) ExamineCreated(c, i, created_mark);
  }
  for (const CellHandle c : unique_) c->info().surface_carved = c->info().carved;
  created_.clear();

  const std::uint32_t mark = ++mark_;
  for (const CellHandle c : dirty_) {
    CellInfo& info = c->info();
    if (info.surface_mark == mark) continue;
    info.surface_mark = mark;
    for (int i = 0; i < 4; ++i) Examine(c, i);
    // Seen now: the facets this cell shares with a dirty cell examined later are judged from this state.
    info.surface_carved = info.carved;
  }
  dirty_.clear();
}

void SurfaceTracker::Forget(const std::vector<CellHandle>& doomed) {
  for (const CellHandle c : doomed) {
    SEMAP_ASSERT(c->info().carved == c->info().surface_carved, "Forget before Sync");
    if (!c->info().carved) continue;  // a surface facet has its carved cell on one side: met from there
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i)->info().carved) continue;
      Erase(OrientedKey(OrientedFacet(c, i)));
    }
  }
}

SurfaceTracker::Key SurfaceTracker::OrientedKey(const SurfaceFacet& f) {
  return CanonicalTriangle({VertexKey(f.vertices[0]), VertexKey(f.vertices[1]), VertexKey(f.vertices[2])});
}

bool SurfaceTracker::IsHullFacet(CellHandle cell, int i) const {
  for (int k = 0; k < 4; ++k) {
    if (k != i && dt_->is_infinite(cell->vertex(k))) return true;
  }
  return false;
}

void SurfaceTracker::InsertIfKept(const SurfaceFacet& facet) {
  const bool steiner = facet.vertices[0]->info().steiner || facet.vertices[1]->info().steiner ||
                       facet.vertices[2]->info().steiner;
  if (!(drop_steiner_ && steiner)) Insert(OrientedKey(facet), facet);
}

void SurfaceTracker::ExamineCreated(CellHandle cell, int i, std::uint32_t created_mark) {
  const CellHandle other = cell->neighbor(i);
  const bool other_created = other->info().surface_mark == created_mark;
  // A facet between two created cells is new (Forget dropped every surface facet of the doomed cells that
  // did not survive): judged once, from the cell first in memory order.
  if (other_created && &*other < &*cell) return;
  if (IsHullFacet(cell, i)) return;
  if (!other_created && other->info().surface_carved) {
    // The old cell's side may hold it (when the doomed cell there before was not carved).
    Erase(OrientedKey(OrientedFacet(other, other->index(cell))));
  }
  const bool carved = cell->info().carved;
  if (carved != other->info().carved) {
    InsertIfKept(carved ? OrientedFacet(cell, i) : OrientedFacet(other, other->index(cell)));
  }
}

void SurfaceTracker::Examine(CellHandle cell, int i) {
  // Between Syncs the surface holds exactly the facets between cells whose surface_carved flags differ, so a
  // facet needs work only where its cells' carved flags moved since they were last seen.
  const CellHandle other = cell->neighbor(i);
  const CellInfo &a = cell->info(), &b = other->info();
  if (a.carved == a.surface_carved && b.carved == b.surface_carved) return;
  if (IsHullFacet(cell, i)) return;
  auto facet_from = [&](bool cell_side) {
    return cell_side ? OrientedFacet(cell, i) : OrientedFacet(other, other->index(cell));
  };
  if (a.surface_carved != b.surface_carved) Erase(OrientedKey(facet_from(a.surface_carved)));
  if (a.carved != b.carved) InsertIfKept(facet_from(a.carved));
}

void SurfaceTracker::Insert(const Key& key, const SurfaceFacet& facet) {
  auto [it, inserted] = facets_.try_emplace(key, facet);
  if (inserted) {
    was_there_.try_emplace(key, false);
  } else {
    it->second = facet;  // same vertices; the facet's cells may be new
  }
}

void SurfaceTracker::Erase(const Key& key) {
  if (facets_.erase(key) > 0) was_there_.try_emplace(key, true);
}

SurfaceChange SurfaceTracker::Take(const AttributeLookup& attributes, Label unlabelled) {
  SurfaceChange change;
  std::vector<SurfaceFacet> added;
  for (const auto& [key, was_there] : was_there_) {
    auto it = facets_.find(key);
    const bool is_there = it != facets_.end();
    if (was_there && !is_there) change.removed.push_back(key);
    if (!was_there && is_there) added.push_back(it->second);
  }
  was_there_.clear();
  // A stable order (the hash map's is not): by facet, then the removed triangles by key.
  std::sort(added.begin(), added.end(),
            [](const SurfaceFacet& x, const SurfaceFacet& y) { return x.id < y.id; });
  std::sort(change.removed.begin(), change.removed.end());
  change.added = FacetsToMesh(added, attributes, unlabelled);
  return change;
}

}  // namespace semap::map_internal
