// An independent 2-manifold checker for the map tests (no CGAL, no engine internals).
#pragma once

#include <string>
#include <vector>

#include "engine/core/mesh.h"

namespace semap::test {

struct ManifoldReport {
  std::vector<std::string> errors;  // empty = manifold
  std::size_t num_boundary_edges = 0;
  bool ok() const { return errors.empty(); }
  std::string Summary() const;  // the first errors, one a line
};

// Checks: indices in range; no degenerate triangle (repeated index or zero area); no duplicate triangle (same
// vertex set); every edge in exactly two triangles (closed) or one or two (`allow_boundary`); consistent
// orientation (each directed edge used once); the triangles around each vertex form a single cycle (a single
// fan, open at the boundary when allowed).
ManifoldReport CheckManifold(const Mesh& mesh, bool allow_boundary);

}  // namespace semap::test
