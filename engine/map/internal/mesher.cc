#include "engine/map/internal/mesher.h"

#include <algorithm>
#include <unordered_set>

#include "engine/core/check.h"

namespace semap::map_internal {

IdentifiedMesh Mesher::ExtractLive() const {
  // Non-regular vertices, and their neighbours on the surface (an edge with more than two facets makes both
  // ends non-regular), get their runs by wedges.
  std::vector<VertexHandle> irregular;
  std::vector<SurfaceFacet> around;
  for (const auto& [key, v] : irregular_) {
    around.clear();
    SurfaceAround(*dt_, v, &around);
    irregular.push_back(v);
    for (const SurfaceFacet& f : around)
      irregular.insert(irregular.end(), f.vertices.begin(), f.vertices.end());
  }
  return ExtractSurfaceMesh(*dt_, rule_, irregular, &fan_copies_, PointAttributes{}.label, position_);
}

IdentifiedMesh Mesher::TakeFinalised() {
  IdentifiedMesh out = std::move(finalised_);
  finalised_ = IdentifiedMesh();
  finalised_index_.clear();
  return out;
}

void Mesher::AddIrregular(const std::vector<VertexHandle>& vertices) {
  for (const VertexHandle v : vertices) irregular_.emplace(&*v, v);
}

void Mesher::ForgetIrregular(const std::vector<VertexHandle>& vertices) {
  for (const VertexHandle v : vertices) irregular_.erase(&*v);
}

void Mesher::RecordFan(VertexHandle v, std::vector<SurfaceFacet>* around) {
  around->clear();
  SurfaceAround(*dt_, v, around);
  around->erase(std::remove_if(around->begin(), around->end(),
                               [&](const SurfaceFacet& f) { return LeftOut(f, rule_); }),
                around->end());
  std::vector<const SurfaceFacet*> fan;
  for (const SurfaceFacet& f : *around) fan.push_back(&f);
  const std::vector<std::uint8_t> copies = FanRuns(*dt_, v, fan, /*regular=*/false);
  const std::uint64_t key = VertexKey(v);
  for (std::size_t f = 0; f < fan.size(); ++f) {
    const FacetKey& id = fan[f]->id;
    auto it =
        fan_copies_.try_emplace(id, std::array<std::uint8_t, 3>{kUnassigned, kUnassigned, kUnassigned}).first;
    it->second[std::find(id.begin(), id.end(), key) - id.begin()] = copies[f];
  }
}

void Mesher::EmitHole(const std::vector<CellHandle>& destroyed, std::uint32_t destroyed_mark,
                      const std::vector<VertexHandle>& removed, const std::vector<VertexHandle>& seam) {
  // The copies of every vertex of the emitted facets, fixed from its whole cycle while the whole surface is
  // still here: the seam's vertices keep them while they stay live and pinned.
  std::vector<SurfaceFacet> around;
  for (const VertexHandle v : seam) {
    if (!v->info().frozen) RecordFan(v, &around);
  }
  for (const VertexHandle v : removed) {
    if (!v->info().frozen) RecordFan(v, &around);
  }
  // Every surface facet inside the hole goes: those through the removed vertices, and those between two
  // destroyed cells whose three vertices stay (the re-triangulation does not keep them).
  std::unordered_set<FacetKey, FacetKeyHash> emitted;
  around.clear();
  for (const CellHandle c : destroyed) {
    if (dt_->is_infinite(c)) continue;
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i)->info().stamp == destroyed_mark && TakenFrom(*dt_, c, i)) {
        around.push_back(OrientedSurfaceFacet(c, i));
      }
    }
  }
  {
    for (const SurfaceFacet& f : around) {
      if (LeftOut(f, rule_) || !emitted.insert(f.id).second) continue;
      const auto copies = fan_copies_.find(f.id);
      SEMAP_ASSERT(copies != fan_copies_.end(), "a finalised facet without the copies of its vertices");
      std::array<std::uint32_t, 3> tri;
      for (int k = 0; k < 3; ++k) {
        const VertexHandle u = f.vertices[k];
        const std::uint64_t key = VertexKey(u);
        std::uint8_t copy = copies->second[std::find(f.id.begin(), f.id.end(), key) - f.id.begin()];
        if (copy == kUnassigned) copy = 0;
        const std::uint64_t id = OutputKey(u, copy);
        auto [it, inserted] =
            finalised_index_.try_emplace(id, std::uint32_t(finalised_.mesh.vertices.size()));
        if (inserted) {
          finalised_.mesh.vertices.push_back(PositionOf(position_, u));
          finalised_.vertex_ids.push_back(id);
          const PointAttributes& a = u->info().attributes;  // the defaults for a Steiner vertex
          finalised_.mesh.labels.push_back(a.label);
          finalised_.mesh.colors_rgb.push_back(a.color_rgb);
        }
        tri[k] = it->second;
      }
      finalised_.mesh.triangles.push_back(tri);
    }
  }
  for (const FacetKey& id : emitted) fan_copies_.erase(id);
}

}  // namespace semap::map_internal
