#include "engine/map/internal/surface_extraction.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

namespace semap::map_internal {
namespace {

constexpr std::array<std::uint8_t, 3> kSteinerColor{128, 128, 128};

bool LexLess(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

}  // namespace

SurfaceFacet OrientedFacet(CellHandle carved_cell, int opposite) {
  SurfaceFacet f;
  for (int k = 0, n = 0; k < 4; ++k) {
    if (k != opposite) f.vertices[n++] = carved_cell->vertex(k);
  }
  // Counter-clockwise seen from the carved side, where the opposite vertex lies.
  if (CGAL::orientation(f.vertices[0]->point(), f.vertices[1]->point(), f.vertices[2]->point(),
                        carved_cell->vertex(opposite)->point()) == CGAL::NEGATIVE) {
    std::swap(f.vertices[1], f.vertices[2]);
  }
  for (int k = 0; k < 3; ++k) f.id[k] = VertexKey(f.vertices[k]);
  std::sort(f.id.begin(), f.id.end());
  return f;
}

void CollectSurface(const Delaunay& dt, bool drop_steiner, std::vector<SurfaceFacet>* facets) {
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    if (!c->info().carved) continue;
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i)->info().carved) continue;
      SurfaceFacet f = OrientedFacet(c, i);
      if (drop_steiner && std::any_of(f.vertices.begin(), f.vertices.end(),
                                      [](VertexHandle v) { return v->info().steiner; })) {
        continue;
      }
      facets->push_back(f);
    }
  }
}

namespace {

// The mesh index of each vertex, by vertex id. Point ids of a live map are nearly contiguous (numbered in
// arrival order, finalised oldest first), so a table over their span replaces a hash map over the ~10^5
// vertices of a live surface; a sparse span (a few ancient points kept) and the Steiner vertices go to hash
// maps.
class VertexIndex {
 public:
  explicit VertexIndex(const std::vector<SurfaceFacet>& facets) {
    std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0;
    for (const SurfaceFacet& f : facets) {
      for (const VertexHandle v : f.vertices) {
        if (v->info().steiner) continue;
        lo = std::min(lo, v->info().id);
        hi = std::max(hi, v->info().id);
      }
    }
    if (lo > hi) return;
    const std::size_t span = std::size_t(hi - lo) + 1;
    if (span <= kMaxSpanPerFacet * facets.size()) {
      first_id_ = lo;
      table_.assign(span, kUnset);
    }
  }
  // The slot of `v`, or kUnset; `slot` may be set through the returned reference.
  std::uint32_t& Slot(VertexHandle v) {
    const std::uint32_t id = v->info().id;
    if (v->info().steiner) return steiner_.try_emplace(id, kUnset).first->second;
    if (!table_.empty()) return table_[id - first_id_];
    return sparse_.try_emplace(id, kUnset).first->second;
  }

  static constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();

 private:
  static constexpr std::size_t kMaxSpanPerFacet = 8;
  std::uint32_t first_id_ = 0;
  std::vector<std::uint32_t> table_;
  std::unordered_map<std::uint32_t, std::uint32_t> steiner_, sparse_;
};

}  // namespace

IdentifiedMesh FacetsToMesh(const std::vector<SurfaceFacet>& facets, Label unlabelled) {
  IdentifiedMesh out;
  Mesh& mesh = out.mesh;
  VertexIndex index(facets);
  mesh.triangles.reserve(facets.size());
  for (const SurfaceFacet& f : facets) {
    std::array<std::uint32_t, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const VertexHandle v = f.vertices[k];
      std::uint32_t& slot = index.Slot(v);
      if (slot == VertexIndex::kUnset) {
        slot = std::uint32_t(mesh.vertices.size());
        mesh.vertices.push_back(ToEigen(v->point()));
        out.vertex_ids.push_back(VertexKey(v));
        if (v->info().steiner) {
          mesh.labels.push_back(unlabelled);
          mesh.colors_rgb.push_back(kSteinerColor);
        } else {
          mesh.labels.push_back(v->info().attributes.label);
          mesh.colors_rgb.push_back(v->info().attributes.color_rgb);
        }
      }
      tri[k] = slot;
    }
    mesh.triangles.push_back(tri);
  }
  return out;
}

std::vector<CellVotes> CollectCellVotes(const Delaunay& dt) {
  std::vector<CellVotes> out;
  out.reserve(dt.number_of_finite_cells());
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    CellVotes v;
    for (int k = 0; k < 4; ++k) v.vertices[k] = ToEigen(c->vertex(k)->point());
    std::sort(v.vertices.begin(), v.vertices.end(), LexLess);
    v.free_fixed = c->info().free_q;
    v.matter_fixed = c->info().matter_q;
    v.carved = c->info().carved;
    out.push_back(v);
  }
  return out;
}

std::size_t CountCarvedCells(const Delaunay& dt) {
  std::size_t n = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) n += c->info().carved ? 1 : 0;
  return n;
}

std::size_t CountFreeCells(const Delaunay& dt) {
  std::size_t n = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) n += c->info().IsFree() ? 1 : 0;
  return n;
}

}  // namespace semap::map_internal
