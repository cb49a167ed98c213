// The live surface of the incremental map, kept up to date from the cells that changed.
#pragma once

#include <unordered_map>
#include <vector>

#include "engine/core/mesh_delta.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// Holds the boundary facets of the carved region (the set CollectSurface reads out of the whole
// triangulation) and updates it from the cells whose carved flag changed or that were created, so that what
// an update costs here grows with what it changed, not with the size of the map. Facets are named by their
// vertex keys, which survive re-triangulation: a facet destroyed and created again with the same vertices
// and the same carved side is no change. Works on a triangulation it does not own; not thread-safe.
class SurfaceTracker {
 public:
  // `drop_steiner`: facets touching a Steiner vertex are not part of the surface (as in CollectSurface).
  SurfaceTracker(const Delaunay* dt, bool drop_steiner) : dt_(dt), drop_steiner_(drop_steiner) {}

  // Cells to examine at the next Sync: cells whose carved flag was written (dirty) and cells just created.
  // Duplicates are fine. Every cell listed must still exist at the next Sync.
  std::vector<CellHandle>* dirty() { return &dirty_; }
  std::vector<CellHandle>* created() { return &created_; }

  // Brings the surface up to date around the dirty cells and empties the list.
  void Sync();

  // Call before `doomed` cells are destroyed, after Sync: drops their facets from the surface. Those the
  // change does not destroy belong to cells it creates, which the caller lists as dirty afterwards.
  void Forget(const std::vector<CellHandle>& doomed);

  // The triangles that entered and left the surface since the last Take (or since construction), as of
  // the last Sync. Vertex ids are vertex keys (VertexKey), attributes come from `attributes`, Steiner
  // vertices are labelled `unlabelled`.
  SurfaceChange Take(const AttributeLookup& attributes, Label unlabelled);

  std::size_t size() const { return facets_.size(); }

 private:
  // An oriented facet: its vertex keys counter-clockwise seen from the carved side, rotated so that the
  // smallest comes first (CanonicalTriangle).
  using Key = std::array<std::uint64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  static Key OrientedKey(const SurfaceFacet& facet);

  // Moves the facet of `cell` opposite vertex `i` from where its cells' surface_carved flags put it to where
  // their carved flags put it: out of the surface, into it, or turned over.
  void Examine(CellHandle cell, int i);
  // The same for a cell created since the last Sync (its flags say nothing of what the surface holds); the
  // created cells carry `created_mark` in surface_mark.
  void ExamineCreated(CellHandle cell, int i, std::uint32_t created_mark);
  bool IsHullFacet(CellHandle cell, int i) const;  // the facet has the infinite vertex
  void InsertIfKept(const SurfaceFacet& facet);    // unless it is a dropped Steiner facet
  void Insert(const Key& key, const SurfaceFacet& facet);
  void Erase(const Key& key);

  const Delaunay* dt_;
  bool drop_steiner_;
  std::unordered_map<Key, SurfaceFacet, KeyHash> facets_;
  // Facets changed since the last Take, each with whether it was in the surface then.
  std::unordered_map<Key, bool, KeyHash> was_there_;
  std::vector<CellHandle> dirty_;
  std::vector<CellHandle> created_;
  std::vector<CellHandle> unique_;  // scratch
  std::uint32_t mark_ = 0;  // Sync's stamp in CellInfo::surface_mark
};

}  // namespace semap::map_internal
