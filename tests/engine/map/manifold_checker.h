// An independent 2-manifold checker for the map tests (no CGAL, no engine internals).
#pragma once

#include <string>
#include <vector>

#include "engine/core/mesh.h"

namespace semap::test {

struct ManifoldReport {
  std::vector<std::string> errors;  // empty = manifold (the first kMaxErrors messages)
  std::size_t num_boundary_edges = 0;
  // Counts of every defect (the messages stop at the first few).
  std::size_t num_bad_triangles = 0;         // index out of range, repeated vertex, zero area, duplicate
  std::size_t num_nonmanifold_edges = 0;     // more than two triangles (or one, when no boundary is allowed)
  std::size_t num_misoriented_edges = 0;     // a directed edge used twice
  std::size_t num_nonmanifold_vertices = 0;  // triangles around the vertex not a single fan
  bool ok() const { return errors.empty(); }
  std::string Summary() const;  // the first errors, one a line
};

// Checks: indices in range; no degenerate triangle (repeated index or zero area); no duplicate triangle (same
// vertex set); every edge in exactly two triangles (closed) or one or two (`allow_boundary`); consistent
// orientation (each directed edge used once); the triangles around each vertex form a single cycle (a single
// fan, open at the boundary when allowed).
ManifoldReport CheckManifold(const Mesh& mesh, bool allow_boundary);

}  // namespace semap::test
