#include "engine/map/internal/seen_holes.h"

#include <unordered_map>

namespace semap::map_internal {
namespace {

// A walk around an edge passes each of its cells once: past this many something is wrong with the
// triangulation, and the walk gives up (no hole is filled through it).
constexpr int kMaxCellsAroundEdge = 1024;

bool OnSeamOrSteiner(const CarvedFacet& f) {
  for (int k = 0; k < 4; ++k) {
    if (k == f.index) continue;
    const VertexInfo& v = f.cell->vertex(k)->info();
    if (v.frozen || v.steiner) return true;
  }
  return false;
}

class HoleFinder {
 public:
  HoleFinder(const Delaunay& dt, int max_facets) : dt_(dt), max_facets_(max_facets) {}

  // Explores the unseen facets connected to `seed` (unseen); true with `hole_` holding them when they make a
  // hole to fill.
  bool Explore(const CarvedFacet& seed) {
    const FacetHandles seed_key = SortedFacet(seed.cell, seed.index);
    if (explored_.count(seed_key)) return false;  // met before: filled since, or not a hole
    ++exploration_;
    hole_.clear();
    Add(seed, seed_key);
    for (std::size_t next = 0; next < hole_.size(); ++next) {
      const CarvedFacet f = hole_[next];
      if (OnSeamOrSteiner(f)) return false;
      for (int e = 0; e < 3; ++e) {
        CarvedFacet g;
        if (!SurfaceNeighbour(dt_, f, e, &g)) return false;
        if (FacetSeen(g.cell, g.index)) continue;
        const FacetHandles key = SortedFacet(g.cell, g.index);
        const auto it = explored_.find(key);
        if (it != explored_.end()) {
          if (it->second == exploration_) continue;  // already in this set
          return false;                              // part of a set explored before that was no hole
        }
        Add(g, key);
        if (int(hole_.size()) > max_facets_) return false;
      }
    }
    return true;
  }
  const std::vector<CarvedFacet>& hole() const { return hole_; }

 private:
  void Add(const CarvedFacet& f, const FacetHandles& key) {
    explored_.emplace(key, exploration_);
    hole_.push_back(f);
  }

  const Delaunay& dt_;
  int max_facets_;
  int exploration_ = 0;
  std::unordered_map<FacetHandles, int, FacetHandlesHash> explored_;  // facet → the exploration that met it
  std::vector<CarvedFacet> hole_;
};

}  // namespace

bool AsCarvedFacet(const Delaunay& dt, CellHandle c, int i, CarvedFacet* out) {
  const CellHandle n = c->neighbor(i);
  if (dt.is_infinite(c) || dt.is_infinite(n) || c->info().IsSealed() || n->info().IsSealed()) return false;
  if (c->info().carved == n->info().carved) return false;
  *out = c->info().carved ? CarvedFacet{c, i} : CarvedFacet{n, n->index(c)};
  return true;
}

bool SurfaceNeighbour(const Delaunay& dt, const CarvedFacet& f, int e, CarvedFacet* out) {
  int facet_index[3];
  for (int k = 0, n = 0; k < 4; ++k) {
    if (k != f.index) facet_index[n++] = k;
  }
  // In the carved cell `cell` around the edge: `cross` is the vertex whose opposite facet leads on around the
  // edge, `entered` the one whose opposite facet the walk came through.
  CellHandle cell = f.cell;
  VertexHandle cross = cell->vertex(facet_index[e]);
  VertexHandle entered = cell->vertex(f.index);
  for (int step = 0; step < kMaxCellsAroundEdge; ++step) {
    const int j = cell->index(cross);
    const CellHandle next = cell->neighbor(j);
    if (dt.is_infinite(next) || next->info().IsSealed()) return false;
    if (!next->info().carved) {
      *out = {cell, j};
      return true;
    }
    // next holds the edge, `entered` and one new vertex; the walk entered it through the facet opposite the
    // new vertex and leaves through the one opposite `entered`.
    const VertexHandle fresh = next->vertex(next->index(cell));
    cross = entered;
    entered = fresh;
    cell = next;
  }
  return false;
}

std::size_t FillUnseenHoles(Delaunay* dt, const std::vector<CellHandle>& cells, int max_facets) {
  if (max_facets <= 0) return 0;
  HoleFinder finder(*dt, max_facets);
  std::size_t marked = 0;
  const auto try_fill = [&](const CarvedFacet& f) {
    if (FacetSeen(f.cell, f.index) || !finder.Explore(f)) return;
    for (const CarvedFacet& h : finder.hole()) MarkFacetSeen(h.cell, h.index);
    marked += finder.hole().size();
  };
  for (std::size_t k = 0; k < cells.size(); ++k) {
    // AsCarvedFacet reads the neighbour across each facet, and the cells are scattered over the map.
    if (k + kPrefetchCells < cells.size()) PrefetchNeighbourRecords(cells[k + kPrefetchCells]);
    const CellHandle c = cells[k];
    for (int i = 0; i < 4; ++i) {
      CarvedFacet f;
      if (!AsCarvedFacet(*dt, c, i, &f)) continue;
      if (!FacetSeen(f.cell, f.index)) {
        try_fill(f);  // its exploration meets its unseen neighbours: they are in its hole, or in no hole
        continue;
      }
      for (int e = 0; e < 3; ++e) {  // a seen facet may close the ring of a hole beside it
        CarvedFacet g;
        if (SurfaceNeighbour(*dt, f, e, &g)) try_fill(g);
      }
    }
  }
  return marked;
}

}  // namespace semap::map_internal
