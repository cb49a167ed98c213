// Incremental mesh streaming: changes between two mesh updates in terms of stable vertex and triangle ids,
// so that a subscriber keeps the mesh up to date without full resends.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/core/mesh.h"

namespace semap {

using VertexId = std::uint64_t;
using TriangleId = std::uint64_t;

// A mesh whose vertices carry stable ids (e.g. the map's point ids). `vertex_ids` is parallel to
// mesh.vertices; triangles index into mesh.vertices as usual.
struct IdentifiedMesh {
  Mesh mesh;
  std::vector<VertexId> vertex_ids;
};

struct MeshDelta {
  std::int64_t frame_id = -1;
  std::vector<TriangleId> removed_triangle_ids;
  // The added triangles (vertex ids) and every vertex they reference, with attributes.
  std::vector<TriangleId> added_triangle_ids;
  std::vector<std::array<VertexId, 3>> added_triangles;
  std::vector<VertexId> vertex_ids;
  std::vector<Eigen::Vector3d> vertex_positions;
  std::vector<std::array<std::uint8_t, 3>> vertex_colors_rgb;  // empty or one per vertex
  std::vector<Label> vertex_labels;                            // empty or one per vertex
  // Triangles (added by this delta or earlier) that belong to finalised parts of the map: they are never
  // removed afterwards. Publishers may send them once for good (io/lcm); applying a delta ignores it.
  std::vector<TriangleId> finalised_triangle_ids;

  bool empty() const { return removed_triangle_ids.empty() && added_triangle_ids.empty(); }
};

// Producer side: turns successive meshes into deltas. A triangle is identified by its three vertex ids in
// order (rotations of the same oriented triangle are the same triangle). Not thread-safe.
class MeshDiffer {
 public:
  // The delta from the previously seen `live` mesh to this one. Triangles of `frozen` (finalised parts of
  // the map that leave the live mesh for good) are added if not yet published and are never removed
  // afterwards: they are forgotten by the differ, which keeps its memory bounded by the live mesh.
  MeshDelta Update(std::int64_t frame_id, const IdentifiedMesh& live, const IdentifiedMesh& frozen = {});

  size_t num_live_triangles() const { return live_.size(); }

 private:
  struct KeyHash {
    size_t operator()(const std::array<VertexId, 3>& k) const;
  };
  struct LiveTriangle {
    TriangleId id = 0;
    std::uint64_t seen = 0;  // generation of the last update that had it
  };
  std::unordered_map<std::array<VertexId, 3>, LiveTriangle, KeyHash> live_;
  TriangleId next_id_ = 1;
  std::uint64_t generation_ = 0;
};

// Subscriber side: applies snapshots and deltas and rebuilds an indexed mesh. It holds the triangles it was
// given and the vertices they reference (a vertex no triangle references any more is forgotten: a delta
// brings again every vertex its added triangles reference). Not thread-safe.
class MeshAccumulator {
 public:
  void Reset();
  // Vertices are upserted; removed ids that are unknown are ignored (a subscriber may join late).
  void Apply(const MeshDelta& delta);
  // The current mesh. Vertex order follows ids, triangle order too.
  Mesh ToMesh() const;
  // Everything accumulated as one delta with the original ids (a snapshot: apply after Reset()).
  MeshDelta AsSnapshot(std::int64_t frame_id) const;
  // Removes the triangles `ids` names (unknown ones are passed over) and returns them as a delta that adds
  // them, with every vertex they reference as it is now; the vertices no triangle left references are
  // forgotten. For a holder that keeps parts of the mesh elsewhere: the finalised triangles, which no delta
  // removes, go to disk (io's MeshFileSink) and the accumulator keeps only the live mesh.
  MeshDelta TakeTriangles(const std::vector<TriangleId>& ids);
  size_t num_triangles() const { return triangles_.size(); }
  size_t num_vertices() const { return vertices_.size(); }
  // Whether any delta applied had vertex colours / labels (the mesh then has them for every vertex).
  bool has_colors() const { return has_colors_; }
  bool has_labels() const { return has_labels_; }

 private:
  struct Vertex {
    Eigen::Vector3d position;
    std::array<std::uint8_t, 3> color_rgb{0, 0, 0};
    Label label = 0;
    std::uint32_t triangles = 0;  // held triangles that reference it
  };
  // Adds `t` to the triangle counts of its vertices (which must be known), or removes it (`step` −1),
  // forgetting the vertices it leaves without triangles.
  void Reference(const std::array<VertexId, 3>& t, int step);
  // Appends vertex `id` to `delta` (its id, position and, as the mesh has them, colour and label).
  void AppendVertex(VertexId id, MeshDelta* delta) const;

  std::unordered_map<VertexId, Vertex> vertices_;
  std::unordered_map<TriangleId, std::array<VertexId, 3>> triangles_;
  bool has_colors_ = false;
  bool has_labels_ = false;
};

// The canonical form of a triangle for comparisons: rotated so that the smallest vertex id comes first.
std::array<VertexId, 3> CanonicalTriangle(const std::array<VertexId, 3>& t);

}  // namespace semap
