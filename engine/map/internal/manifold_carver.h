// Keeps the set of carved (free-space) cells a region whose boundary is a 2-manifold.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// The boundary of the carved region is a 2-manifold iff at every vertex v the boundary facets around v form a
// single cycle on v's link (or there are none): then each edge has exactly two boundary facets and each
// vertex a disk-like umbrella (the vertex/edge conditions of Litvinov–Lhuillier and Piazza et al.). Carving
// or uncarving one cell changes only the links of its four vertices, so each change is tested on those only.
// Infinite cells are never carved, and pinned cells (IsPinned: the seams of an incremental map's
// finalisation) never change. Works on a triangulation it does not own; not thread-safe.
class ManifoldCarver {
 public:
  // `max_passes`: Grow() retries the cells that failed, while a pass still carves something, at most this
  // many passes. `fill_cost_q`: what Repair charges, in fixed-point vote units, for carving one cell that is
  // not free (on top of its matter excess); negative: Repair never carves, it only uncarves.
  ManifoldCarver(Delaunay* dt, int max_passes, std::int64_t fill_cost_q = -1)
      : dt_(dt), max_passes_(max_passes), fill_cost_q_(fill_cost_q) {}

  // True when the boundary facets around `v` form zero or one cycle on its link.
  bool IsRegular(VertexHandle v);

  // Carves `cell` if the boundary stays manifold; returns whether it did.
  bool TryCarve(CellHandle cell);

  // Region growing: repeatedly carves the free, uncarved cell with the highest free vote among the candidates
  // and the free neighbours of cells carved so far, when the boundary stays manifold. A cell that fails is
  // retried when one of its neighbours is carved later. Candidates need not be adjacent to the region (a
  // seed is). Returns the number of cells carved, and appends them to `carved_cells` (when not null).
  std::size_t Grow(const std::vector<CellHandle>& candidates,
                   std::vector<CellHandle>* carved_cells = nullptr);

  // Makes every vertex of `vertices` regular again (and the vertices of the cells it changes), after carving
  // or uncarving cells without the manifold test. At a non-regular vertex v it applies the cheaper of
  //  - fill: carve every uncarved cell around v (then v is inside the region), costing each cell's matter
  //    excess plus fill_cost_q; only with `allow_fill`, and only once per cell;
  //  - keep: uncarve the carved cells around v outside the facet-connected component with the largest free
  //    excess (free − matter), costing the free excess given up;
  // and, when v's carved cells are one component that still pinches, uncarves its weakest cell on the
  // boundary, until v is regular. Each cell changes at most twice, so the repair ends. Appends the changed
  // cells (carved or uncarved) to `changed`.
  void Repair(std::vector<VertexHandle> vertices, bool allow_fill, std::vector<CellHandle>* changed);

  // Carves every free cell of `cells` at once, restores the manifold with Repair (fill allowed), then grows
  // from the free cells still uncarved (Grow). Far fewer free cells are left out than by growth alone, whose
  // greedy order blocks itself (see MapOptions::extraction). Appends the cells Repair changed, and those the
  // growth carved, to `changed`.
  // Returns the number of cells carved by the first step and by the growth.
  // `also_repair`: more vertices to make regular in the same repair (e.g. the boundary of a re-triangulated
  // region, whose new cells sit beside carved old ones).
  std::size_t CarveAndRepair(const std::vector<CellHandle>& cells, std::vector<CellHandle>* changed,
                             const std::vector<VertexHandle>& also_repair = {});

  // Uncarves every carved cell incident to `vertices`, then repairs around them (Repair, without fill).
  // Appends the uncarved cells to `uncarved`.
  void UncarveStars(const std::vector<VertexHandle>& vertices, std::vector<CellHandle>* uncarved);

  std::uint64_t num_tests() const { return num_tests_; }
  // Vertices Repair left non-regular because every change that would fix them touches a pinned cell.
  std::uint64_t num_unrepaired() const { return num_unrepaired_; }
  // Those vertices since the last call (they may be regular again by now).
  std::vector<VertexHandle> TakeUnrepaired() { return std::move(unrepaired_); }

 private:
  // Whether vertex `cell->vertex(iv)`, regular now, stays regular once the uncarved `cell` is carved, decided
  // from the cells around `cell` only (see TryCarve); kUnknown when only the full link test can tell.
  enum class Verdict { kRegular, kNotRegular, kUnknown };
  Verdict CarveVerdict(CellHandle cell, int iv) const;
  // True when a carved cell is incident to the edge (cell->vertex(i), cell->vertex(j)).
  bool EdgeTouchesCarved(CellHandle cell, int i, int j) const;
  // One repair step at the non-regular vertex v (see Repair); pushes the vertices of changed cells. False
  // when no step is possible without changing a pinned cell.
  bool RepairStep(VertexHandle v, bool allow_fill, std::vector<VertexHandle>* stack,
                  std::vector<CellHandle>* changed);
  // Sorts `vertices` by position (x, then y, then z) and keeps each vertex once.
  void SortByPosition(std::vector<VertexHandle>* vertices);

  Delaunay* dt_;
  int max_passes_;
  std::int64_t fill_cost_q_;
  std::unordered_set<const void*> settled_;  // cells changed by the running Repair
  std::unordered_set<const void*> regular_;  // vertices the running Repair found regular, unchanged since
  std::vector<CellHandle> star_;             // scratch: a vertex's cells
  std::vector<int> component_;               // scratch: component of each star cell
  std::vector<CellHandle> cells_;            // scratch
  std::vector<std::pair<VertexHandle, VertexHandle>> edges_;  // scratch: link edges
  std::vector<VertexHandle> ends_;                            // scratch
  struct PositionKey {
    std::array<double, 3> xyz;
    VertexHandle vertex;
  };
  std::vector<PositionKey> position_keys_;  // scratch: SortByPosition
  std::uint64_t num_tests_ = 0;
  std::uint64_t num_unrepaired_ = 0;
  std::vector<VertexHandle> unrepaired_;
};

}  // namespace semap::map_internal
