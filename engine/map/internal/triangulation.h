// The CGAL triangulation behind the map. Private to engine/map: never include it from a public header.
#pragma once

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/tags.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "engine/core/class_map.h"

namespace semap::map_internal {

inline constexpr std::uint32_t kNoId = std::numeric_limits<std::uint32_t>::max();

// What a data point brings to the mesh (Steiner vertices keep the defaults).
struct PointAttributes {
  Label label = 0;
  std::array<std::uint8_t, 3> color_rgb{0, 0, 0};
};

struct VertexInfo {
  std::uint32_t id = kNoId;  // point id, or Steiner node slot when `steiner`
  bool steiner = false;
  // On a seam of finalisation (incremental map): its surface fan is final, so every cell around it keeps its
  // carving for good (see CellInfo::Pinned).
  bool frozen = false;
  // Bumped each time the output moves the vertex to its fused estimate (map.fuse_output_sigmas): part of
  // its output id, so that a mesh delta re-sends its triangles at the new position.
  std::uint16_t output_version = 0;
  std::uint32_t stamp = 0;     // scratch mark for set membership during one update
  PointAttributes attributes;  // fits in the padding: VertexInfo stays 16 bytes
};

// One (ray, trace epoch) entry of a cell's ray list. An entry is live while the ray's epoch equals `epoch`;
// untracing a ray bumps its epoch, so stale entries are dropped lazily (see RayRegistry::AddRef).
struct RayRef {
  std::uint32_t ray = kNoId;
  std::uint32_t epoch = 0;
};

// Votes are fixed-point integers (VoteScale units per unit weight): sums are exact and order independent, so
// untracing a ray restores the previous value bit for bit, and incremental votes equal batch votes exactly.
struct CellInfo {
  std::int64_t free_q = 0;
  std::int64_t matter_q = 0;
  bool carved = false;  // inside the manifold free-space region
  // Bit i: a view saw the facet opposite vertex i as a surface (its centroid at the depth of the pixel it
  // projects to; map.visibility: depth). Set on both cells of the facet, so that it survives the insertions
  // that rebuild one of them.
  std::uint8_t seen_facets = 0;
  // A cell filling the hole left by finalised vertices (incremental map): never carved, it stands for the
  // released cells it replaced. Each of its facets on the hole's boundary keeps the carving of the released
  // cell that was behind it (bit i: the facet opposite vertex i), so the surface there stays what it was.
  std::uint8_t sealed = 0;    // kSealed | facet carving bits, or 0
  std::uint32_t stamp = 0;    // scratch mark for set membership during one update
  std::uint32_t created = 0;  // mark of the update that created the cell (incremental map)
  std::vector<RayRef> rays;   // rays whose trace gave this cell a vote (may hold stale entries)

  bool IsFree() const { return free_q > matter_q; }
  bool IsSealed() const { return sealed != 0; }
  // Whether the cell counts as carved seen across its facet opposite vertex `i`.
  bool CarvedAcross(int i) const { return IsSealed() ? ((sealed >> i) & 1) != 0 : carved; }
  // Whether the cell counts as carved across at least one of its facets.
  bool CarvedAcrossAny() const { return IsSealed() ? (sealed & ~kSealed) != 0 : carved; }

  static constexpr std::uint8_t kSealed = 0x10;
};

// A cell whose carving may never change: sealed, or incident to a frozen (seam) vertex.
template <class C>
bool IsPinned(const C& cell) {
  if (cell->info().IsSealed()) return true;
  for (int k = 0; k < 4; ++k) {
    if (cell->vertex(k)->info().frozen) return true;
  }
  return false;
}

// A vertex or cell base that CGAL orders by creation instead of by address. CGAL compares handles (operator<)
// inside its algorithms, e.g. the std::map of facets that vertex removal re-triangulates a hole from; by
// address, that order follows where the allocator put the containers' blocks, which depends on the other
// threads' allocations and frees: the same frames gave different meshes once vertices were removed
// (finalisation, the fused vertices that move or leave). With a time stamp (CGAL's Has_timestamp, made for
// Mesh_3's determinism) Compact_container numbers each element as it is created and handles compare by that
// number.
template <class Base>
class CreationOrdered : public Base {
 public:
  using Has_timestamp = CGAL::Tag_true;
  using Base::Base;
  template <typename Tds2>
  struct Rebind_TDS {
    using Other = CreationOrdered<typename Base::template Rebind_TDS<Tds2>::Other>;
  };
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& stamp) { time_stamp_ = stamp; }

 private:
  std::size_t time_stamp_ = std::size_t(-1);  // unset: Compact_container gives the next number
};

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CreationOrdered<CGAL::Triangulation_vertex_base_with_info_3<VertexInfo, Kernel>>;
using Cb = CreationOrdered<CGAL::Triangulation_cell_base_with_info_3<CellInfo, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
using Point = Delaunay::Point;
using VertexHandle = Delaunay::Vertex_handle;
// The ray walks read vertices all the time: keep them small (point + cell handle + this + time stamp = 56
// bytes).
static_assert(sizeof(VertexInfo) <= 16, "VertexInfo grew: a CGAL vertex would take another 8 bytes");
using CellHandle = Delaunay::Cell_handle;

// Whether the facet of `c` opposite vertex `i` was seen as a surface (the bit of either of its cells).
inline bool FacetSeen(CellHandle c, int i) {
  const CellHandle n = c->neighbor(i);
  return ((c->info().seen_facets >> i) & 1) != 0 || ((n->info().seen_facets >> n->index(c)) & 1) != 0;
}
// Marks the facet of `c` opposite vertex `i` seen, in both its cells: the bit survives whichever is rebuilt
// next (an insertion or a finalisation rebuilds the cells on one side of a facet it keeps).
inline void MarkFacetSeen(CellHandle c, int i) {
  const CellHandle n = c->neighbor(i);
  c->info().seen_facets |= std::uint8_t(1u << i);
  n->info().seen_facets |= std::uint8_t(1u << n->index(c));
}

// How far ahead of the cell it is at a loop over scattered cells fetches what it will read of them (8 cells:
// the distance that hid the misses of the vote, surface and hole loops; bench/results/frame-rate.md, "What
// changed (200 urban frames, PS, half resolution unless said)").
inline constexpr std::size_t kPrefetchCells = 8;
// Starts fetching the records of the neighbours of `c` (carving, sealing and seen bits, as NeighbourCarved,
// AsCarvedFacet and FacetSeen read them): a loop over cells scattered over the map calls it for the cell
// kPrefetchCells ahead, so that those reads do not wait for memory.
inline void PrefetchNeighbourRecords(CellHandle c) {
  for (int i = 0; i < 4; ++i) __builtin_prefetch(&c->neighbor(i)->info().sealed);  // with `carved`
}

// A facet by its three vertex handles, sorted: names a facet across a re-triangulation that keeps it.
using FacetHandles = std::array<const void*, 3>;
struct FacetHandlesHash {
  std::size_t operator()(const FacetHandles& t) const {
    std::size_t h = 0;
    for (const void* k : t) h = h * 0x9E3779B97F4A7C15ull + std::hash<const void*>()(k);
    return h;
  }
};
inline FacetHandles SortedFacet(CellHandle c, int opposite) {
  FacetHandles f;
  for (int k = 0, n = 0; k < 4; ++k) {
    if (k != opposite) f[n++] = &*c->vertex(k);
  }
  std::sort(f.begin(), f.end());
  return f;
}

inline Point ToPoint(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }
inline Eigen::Vector3d ToEigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace semap::map_internal
