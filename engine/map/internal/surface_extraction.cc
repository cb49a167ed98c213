#include "engine/map/internal/surface_extraction.h"

#include <algorithm>
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

IdentifiedMesh FacetsToMesh(const std::vector<SurfaceFacet>& facets, const AttributeLookup& attributes,
                            Label unlabelled) {
  IdentifiedMesh out;
  Mesh& mesh = out.mesh;
  std::unordered_map<const void*, std::uint32_t> index;
  index.reserve(facets.size());
  mesh.triangles.reserve(facets.size());
  for (const SurfaceFacet& f : facets) {
    std::array<std::uint32_t, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const VertexHandle v = f.vertices[k];
      auto [it, inserted] = index.try_emplace(&*v, std::uint32_t(mesh.vertices.size()));
      if (inserted) {
        mesh.vertices.push_back(ToEigen(v->point()));
        out.vertex_ids.push_back(VertexKey(v));
        if (v->info().steiner) {
          mesh.labels.push_back(unlabelled);
          mesh.colors_rgb.push_back(kSteinerColor);
        } else {
          const PointAttributes a = attributes(v->info().id);
          mesh.labels.push_back(a.label);
          mesh.colors_rgb.push_back(a.color_rgb);
        }
      }
      tri[k] = it->second;
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
