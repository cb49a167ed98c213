// Keeps the set of carved (free-space) cells a region whose boundary is a 2-manifold.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// The boundary of the carved region is a 2-manifold iff at every vertex v the boundary facets around v form a
// single cycle on v's link (or there are none): then each edge has exactly two boundary facets and each
// vertex a disk-like umbrella (the vertex/edge conditions of Litvinov–Lhuillier and Piazza et al.). Carving
// or uncarving one cell changes only the links of its four vertices, so each change is tested on those only.
// Infinite cells are never carved. Works on a triangulation it does not own; not thread-safe.
class ManifoldCarver {
 public:
  // `max_passes`: Grow() retries the cells that failed, while a pass still carves something, at most this
  // many passes.
  ManifoldCarver(Delaunay* dt, int max_passes) : dt_(dt), max_passes_(max_passes) {}

  // True when the boundary facets around `v` form zero or one cycle on its link.
  bool IsRegular(VertexHandle v);

  // Carves `cell` if the boundary stays manifold; returns whether it did.
  bool TryCarve(CellHandle cell);

  // Region growing: repeatedly carves the free, uncarved cell with the highest free vote among the candidates
  // and the free neighbours of cells carved so far, when the boundary stays manifold. A cell that fails is
  // retried when one of its neighbours is carved later. Candidates need not be adjacent to the region (a
  // seed is). Returns the number of cells carved.
  std::size_t Grow(const std::vector<CellHandle>& candidates);

  // Local shrink after the triangulation changed around `vertices`: uncarves the whole star of every
  // non-regular vertex, repeating on the vertices of the uncarved cells, until all are regular. Appends the
  // uncarved cells to `uncarved`.
  void Repair(std::vector<VertexHandle> vertices, std::vector<CellHandle>* uncarved);

  // Uncarves every carved cell incident to `vertices`, then repairs around them (Repair). Appends the
  // uncarved cells to `uncarved`.
  void UncarveStars(const std::vector<VertexHandle>& vertices, std::vector<CellHandle>* uncarved);

  std::uint64_t num_tests() const { return num_tests_; }

 private:
  // Whether vertex `cell->vertex(iv)`, regular now, stays regular once the uncarved `cell` is carved, decided
  // from the cells around `cell` only (see TryCarve); kUnknown when only the full link test can tell.
  enum class Verdict { kRegular, kNotRegular, kUnknown };
  Verdict CarveVerdict(CellHandle cell, int iv) const;
  // True when a carved cell is incident to the edge (cell->vertex(i), cell->vertex(j)).
  bool EdgeTouchesCarved(CellHandle cell, int i, int j) const;

  Delaunay* dt_;
  int max_passes_;
  std::vector<CellHandle> cells_;                             // scratch
  std::vector<std::pair<VertexHandle, VertexHandle>> edges_;  // scratch: link edges
  std::vector<VertexHandle> ends_;                            // scratch
  std::uint64_t num_tests_ = 0;
};

}  // namespace semap::map_internal
