// Test support: a triangulation of a random cloud with a carved manifold region whose surface runs through
// it.
#pragma once

#include <random>

#include "engine/map/internal/manifold_carver.h"
#include "engine/map/internal/triangulation.h"

namespace semap::map_internal::test {

// 1,500 points in a 10 m cube (point ids 0..1499); the cells on the x < 5 side free, the others matter, the
// free side grown from one seed: the surface runs along x = 5 and the hull around the free side.
inline void CarveHalfCloud(Delaunay* dt) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> coordinate(0.0, 10.0);
  for (std::uint32_t i = 0; i < 1500; ++i) {
    const VertexHandle v = dt->insert(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
    v->info().id = i;
  }
  std::uniform_int_distribution<std::int64_t> votes(1, 100);
  for (auto c = dt->finite_cells_begin(); c != dt->finite_cells_end(); ++c) {
    double x = 0.0;
    for (int k = 0; k < 4; ++k) x += 0.25 * c->vertex(k)->point().x();
    (x < 5.0 ? c->info().free_q : c->info().matter_q) = votes(rng);
  }
  ManifoldCarver carver(dt, /*max_passes=*/3);
  carver.Grow({dt->locate(Point(2.5, 5.0, 5.0))});
}

// The finite vertices within `radius_m` of `centre`.
inline std::vector<VertexHandle> VerticesNear(const Delaunay& dt, const Eigen::Vector3d& centre,
                                              double radius_m) {
  std::vector<VertexHandle> out;
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    if ((ToEigen(v->point()) - centre).norm() < radius_m) out.push_back(v);
  }
  return out;
}

// The cells around `vertices`, each once, stamped `mark`.
inline std::vector<CellHandle> StarsOf(const Delaunay& dt, const std::vector<VertexHandle>& vertices,
                                       std::uint32_t mark) {
  std::vector<CellHandle> cells, star;
  for (const VertexHandle v : vertices) {
    star.clear();
    dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == mark) continue;
      c->info().stamp = mark;
      cells.push_back(c);
    }
  }
  return cells;
}

}  // namespace semap::map_internal::test
