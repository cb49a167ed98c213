// The incremental map's output surface: the live mesh read off the triangulation, and the triangles of the
// regions finalisation releases, emitted once, with the same vertex copies on both sides of each seam.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/core/mesh_delta.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// The mesher of the incremental map. Reads the triangulation it is given (never writes it, but for the marks
// CGAL's own star walks set and clear) and keeps what the output needs across updates: the finalised
// triangles not yet taken; the copies of pinched vertices fixed at the seams of finalisation (FanCopies: a
// seam vertex's fan, part emitted and part live, keeps the copies its whole cycle had); the vertices the
// carver left non-regular, whose runs are found by wedges. Not thread-safe.
class Mesher {
 public:
  Mesher(const Delaunay* dt, const EmitRule& rule, VertexPosition position = {})
      : dt_(dt), rule_(rule), position_(std::move(position)) {}

  // The live surface (the rule's facets left out), with stable vertex ids (surface_extraction.h).
  IdentifiedMesh ExtractLive() const;
  // The finalised triangles emitted since the last call, with the same vertex ids; each once.
  IdentifiedMesh TakeFinalised();

  // A finalisation is about to remove `removed`, destroying `destroyed` (their stars, stamped
  // `destroyed_mark`): emits the surface facets inside the hole (between two destroyed cells) as finalised
  // triangles, with the copies of the removed vertices and of the `seam` (the staying vertices of the touched
  // surface, which freeze) fixed from their whole cycles while the whole surface is still there.
  void EmitHole(const std::vector<CellHandle>& destroyed, std::uint32_t destroyed_mark,
                const std::vector<VertexHandle>& removed, const std::vector<VertexHandle>& seam);

  // Vertices the carver could not make regular (beside a seam, where every fix would change a pinned cell):
  // the output gives each of their wedges' runs its own copy.
  void AddIrregular(const std::vector<VertexHandle>& vertices);
  // `vertices` are about to be removed from the triangulation.
  void ForgetIrregular(const std::vector<VertexHandle>& vertices);
  bool IsIrregular(VertexHandle v) const { return irregular_.count(&*v) != 0; }

 private:
  // Fixes in fan_copies_ the copy of `v` in each emitted facet of its cycle (`around`: scratch).
  void RecordFan(VertexHandle v, std::vector<SurfaceFacet>* around);

  const Delaunay* dt_;
  EmitRule rule_;
  VertexPosition position_;  // where the output puts a vertex (empty: its triangulation position)
  IdentifiedMesh finalised_;
  std::unordered_map<std::uint64_t, std::uint32_t> finalised_index_;  // copy key → finalised_ vertex
  FanCopies fan_copies_;  // the copies at frozen vertices (and, during a finalisation, at the removed ones)
  std::unordered_map<const void*, VertexHandle> irregular_;  // removed with their vertices
};

}  // namespace semap::map_internal
