#include "engine/map/internal/surface_extraction.h"

#include <algorithm>
#include <limits>
#include <numeric>
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
  // Counter-clockwise seen from the carved side, where the opposite vertex lies: a finite cell of a CGAL
  // triangulation is positively oriented, and CGAL's vertex triple of a facet is ordered counter-clockwise
  // seen from the facet's opposite vertex in such a cell (no orientation test: tests/engine/map/
  // surface_extraction_test.cc holds the two against each other).
  SurfaceFacet f;
  for (int k = 0; k < 3; ++k) f.vertices[k] = carved_cell->vertex(Delaunay::vertex_triple_index(opposite, k));
  for (int k = 0; k < 3; ++k) f.id[k] = VertexKey(f.vertices[k]);
  std::sort(f.id.begin(), f.id.end());
  return f;
}

SurfaceFacet OrientedSurfaceFacet(CellHandle c, int i) {
  SurfaceFacet f = OrientedFacet(c, i);
  if (!c->info().CarvedAcross(i)) std::swap(f.vertices[1], f.vertices[2]);
  f.unseen = !FacetSeen(c, i);
  return f;
}

bool LeftOut(const SurfaceFacet& f, const EmitRule& rule) {
  if (rule.drop_unseen && f.unseen) return true;
  return rule.drop_steiner &&
         std::any_of(f.vertices.begin(), f.vertices.end(), [](VertexHandle v) { return v->info().steiner; });
}

void CollectSurface(const Delaunay& dt, const EmitRule& rule, std::vector<SurfaceFacet>* facets,
                    std::vector<VertexHandle>* open) {
  // A cell carved across none of its facets yields a facet only towards an infinite neighbour (TakenFrom):
  // the cells on the convex hull, listed first, so that the other uncarved cells (most of the map) are passed
  // over without reading their neighbours.
  std::vector<CellHandle> hull;
  if (dt.dimension() == 3) {
    std::vector<CellHandle> infinite;
    dt.incident_cells(dt.infinite_vertex(), std::back_inserter(infinite));
    for (const CellHandle c : infinite) hull.push_back(c->neighbor(c->index(dt.infinite_vertex())));
    std::sort(hull.begin(), hull.end());
  }
  // The cells that can hold a facet are listed first, in the container's order; then their facets are read
  // with the neighbours of the cell kPrefetchCells ahead (and that cell's own neighbour list, twice as far)
  // already on their way: deciding whether a facet is on the surface reads the neighbour across it, and
  // those reads, scattered over ~10^5 carved cells, were where this pass spent 82 % of its time (200 urban
  // frames; bench/results/frame-rate.md, "What changed (200 urban frames, PS, half resolution unless said)").
  std::vector<CellHandle> candidates;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    if (c->info().CarvedAcrossAny() || std::binary_search(hull.begin(), hull.end(), CellHandle(c))) {
      candidates.push_back(c);
    }
  }
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (k + 2 * kPrefetchCells < candidates.size()) __builtin_prefetch(&*candidates[k + 2 * kPrefetchCells]);
    if (k + kPrefetchCells < candidates.size()) PrefetchNeighbourRecords(candidates[k + kPrefetchCells]);
    const CellHandle c = candidates[k];
    for (int i = 0; i < 4; ++i) {
      if (!TakenFrom(dt, c, i)) continue;
      SurfaceFacet f = OrientedSurfaceFacet(c, i);
      if (LeftOut(f, rule)) {
        if (open) open->insert(open->end(), f.vertices.begin(), f.vertices.end());
        continue;
      }
      facets->push_back(f);
    }
  }
}

void SurfaceAround(const Delaunay& dt, VertexHandle v, std::vector<SurfaceFacet>* facets) {
  std::vector<CellHandle> star;
  dt.incident_cells(v, std::back_inserter(star));
  for (const CellHandle c : star) {
    if (dt.is_infinite(c)) continue;
    for (int i = 0; i < 4; ++i) {
      if (c->vertex(i) != v && TakenFrom(dt, c, i)) facets->push_back(OrientedSurfaceFacet(c, i));
    }
  }
}

namespace {

// The vertex of `f` other than `a` and `b`.
VertexHandle Third(const SurfaceFacet& f, VertexHandle a, VertexHandle b) {
  for (const VertexHandle u : f.vertices) {
    if (u != a && u != b) return u;
  }
  return VertexHandle();
}

// Around the edge (v, w), in the ring of its cells: the third vertices of the two surface facets bounding
// each carved wedge (a maximal run of carved cells). Cells around a vertex that is not frozen are not sealed.
std::vector<std::pair<VertexHandle, VertexHandle>> WedgeBounds(const Delaunay& dt, VertexHandle v,
                                                               VertexHandle w) {
  std::vector<std::pair<VertexHandle, VertexHandle>> wedges;
  CellHandle c;
  int i = 0, j = 0;
  if (!dt.is_edge(v, w, c, i, j)) return wedges;
  std::vector<CellHandle> ring;
  const Delaunay::Cell_circulator start = dt.incident_cells(c, i, j);
  Delaunay::Cell_circulator it = start;
  do ring.push_back(it);
  while (++it != start);
  const std::size_t m = ring.size();
  std::size_t first_uncarved = m;
  for (std::size_t k = 0; k < m && first_uncarved == m; ++k) {
    if (!ring[k]->info().carved) first_uncarved = k;
  }
  if (first_uncarved == m) return wedges;
  // The facet between ring cells a and b (neighbours around the edge): its vertex other than v and w.
  auto shared = [&](CellHandle a, CellHandle b) {
    for (int k = 0; k < 4; ++k) {
      const VertexHandle u = b->vertex(k);
      if (u != v && u != w && a->has_vertex(u)) return u;
    }
    return VertexHandle();
  };
  VertexHandle entered;
  for (std::size_t n = 0; n < m; ++n) {
    const CellHandle a = ring[(first_uncarved + n) % m], b = ring[(first_uncarved + n + 1) % m];
    if (a->info().carved == b->info().carved) continue;
    if (b->info().carved) {
      entered = shared(a, b);
    } else {
      wedges.emplace_back(entered, shared(a, b));
    }
  }
  return wedges;
}

}  // namespace

std::vector<std::uint8_t> FanRuns(const Delaunay& dt, VertexHandle v,
                                  const std::vector<const SurfaceFacet*>& fan, bool regular) {
  const std::size_t n = fan.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  // Facets sharing the edge (v, w) are one run where they bound the same carved wedge around it (an edge of
  // a regular vertex has one wedge; one of a non-regular vertex may have several: then it is cut).
  std::unordered_map<const void*, std::vector<std::size_t>> at;
  for (std::size_t f = 0; f < n; ++f) {
    for (const VertexHandle w : fan[f]->vertices) {
      if (w != v) at[&*w].push_back(f);
    }
  }
  for (const auto& [key, facets] : at) {
    if (facets.size() < 2) continue;
    if (regular && facets.size() == 2) {
      // The edge's two surface facets bound its one carved wedge.
      parent[find(facets[0])] = find(facets[1]);
      continue;
    }
    VertexHandle edge_end;
    for (const VertexHandle u : fan[facets[0]]->vertices) {
      if (&*u == key) edge_end = u;
    }
    // A non-manifold edge (several wedges) is cut: its facets join no run through it, so that no copy of v
    // meets the edge more than twice even where two wedges' runs close up around v.
    const auto wedges = WedgeBounds(dt, v, edge_end);
    if (wedges.size() > 1) continue;
    for (const auto& [a, b] : wedges) {
      std::size_t fa = n, fb = n;
      for (std::size_t f : facets) {
        const VertexHandle x = Third(*fan[f], v, edge_end);
        if (x == a) fa = f;
        if (x == b) fb = f;
      }
      if (fa < n && fb < n) parent[find(fa)] = find(fb);
    }
  }
  // Runs by their smallest facet id.
  std::unordered_map<std::size_t, FacetKey> smallest;
  for (std::size_t f = 0; f < n; ++f) {
    auto [it, inserted] = smallest.try_emplace(find(f), fan[f]->id);
    if (!inserted) it->second = std::min(it->second, fan[f]->id);
  }
  std::vector<std::pair<FacetKey, std::size_t>> runs;
  for (const auto& [root, key] : smallest) runs.emplace_back(key, root);
  std::sort(runs.begin(), runs.end());
  std::unordered_map<std::size_t, std::uint8_t> copy_of;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    copy_of[runs[r].second] = std::uint8_t(std::min<std::size_t>(r, kUnassigned - 1));
  }
  std::vector<std::uint8_t> copies(n);
  for (std::size_t f = 0; f < n; ++f) copies[f] = copy_of[find(f)];
  return copies;
}

void AssignCopies(const Delaunay& dt, std::vector<SurfaceFacet>* facets,
                  const std::vector<VertexHandle>& open, const std::vector<VertexHandle>& irregular,
                  const FanCopies* frozen) {
  if (frozen && !frozen->empty()) {
    for (SurfaceFacet& f : *facets) {
      const bool any_frozen =
          f.vertices[0]->info().frozen || f.vertices[1]->info().frozen || f.vertices[2]->info().frozen;
      if (!any_frozen) continue;
      const auto it = frozen->find(f.id);
      if (it == frozen->end()) continue;
      for (int k = 0; k < 3; ++k) {
        if (!f.vertices[k]->info().frozen) continue;  // copies of the others: from their runs now
        const std::size_t slot = std::find(f.id.begin(), f.id.end(), VertexKey(f.vertices[k])) - f.id.begin();
        if (it->second[slot] != kUnassigned) f.copy[k] = it->second[slot];
      }
    }
  }
  if (open.empty() && irregular.empty()) return;
  struct Fan {
    VertexHandle vertex;
    bool regular = true;
    std::vector<std::size_t> facets;
  };
  std::unordered_map<const void*, Fan> fans;
  for (const VertexHandle v : irregular) {
    if (!v->info().frozen) fans.try_emplace(&*v, Fan{v, false, {}});
  }
  for (const VertexHandle v : open) {
    if (!v->info().frozen) fans.try_emplace(&*v, Fan{v, true, {}});
  }
  if (fans.empty()) return;
  for (std::size_t f = 0; f < facets->size(); ++f) {
    for (const VertexHandle v : (*facets)[f].vertices) {
      const auto it = fans.find(&*v);
      if (it != fans.end()) it->second.facets.push_back(f);
    }
  }
  std::vector<const SurfaceFacet*> fan;
  for (const auto& [key, entry] : fans) {
    if (entry.facets.size() < 2) continue;
    fan.clear();
    for (std::size_t f : entry.facets) fan.push_back(&(*facets)[f]);
    const std::vector<std::uint8_t> copies = FanRuns(dt, entry.vertex, fan, entry.regular);
    for (std::size_t j = 0; j < entry.facets.size(); ++j) {
      SurfaceFacet& facet = (*facets)[entry.facets[j]];
      for (int k = 0; k < 3; ++k) {
        if (facet.vertices[k] == entry.vertex) facet.copy[k] = copies[j];
      }
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
  // The slot of copy `copy` of `v`, or kUnset; `slot` may be set through the returned reference.
  std::uint32_t& Slot(VertexHandle v, std::uint8_t copy) {
    if (copy != 0) return copies_.try_emplace(CopyKey(VertexKey(v), copy), kUnset).first->second;
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
  std::unordered_map<std::uint64_t, std::uint32_t> copies_;
};

}  // namespace

IdentifiedMesh FacetsToMesh(const std::vector<SurfaceFacet>& facets, Label unlabelled,
                            const VertexPosition& position) {
  IdentifiedMesh out;
  Mesh& mesh = out.mesh;
  VertexIndex index(facets);
  mesh.triangles.reserve(facets.size());
  for (const SurfaceFacet& f : facets) {
    std::array<std::uint32_t, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const VertexHandle v = f.vertices[k];
      std::uint32_t& slot = index.Slot(v, f.copy[k]);
      if (slot == VertexIndex::kUnset) {
        slot = std::uint32_t(mesh.vertices.size());
        mesh.vertices.push_back(PositionOf(position, v));
        out.vertex_ids.push_back(OutputKey(v, f.copy[k]));
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

IdentifiedMesh ExtractSurfaceMesh(const Delaunay& dt, const EmitRule& rule,
                                  const std::vector<VertexHandle>& irregular, const FanCopies* frozen,
                                  Label unlabelled, const VertexPosition& position) {
  std::vector<SurfaceFacet> facets;
  std::vector<VertexHandle> open;
  CollectSurface(dt, rule, &facets, &open);
  AssignCopies(dt, &facets, open, irregular, frozen);
  return FacetsToMesh(facets, unlabelled, position);
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
    v.sealed = c->info().IsSealed();
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
