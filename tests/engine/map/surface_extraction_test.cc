#include "engine/map/internal/surface_extraction.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace semap::map_internal {
namespace {

// FacetsToMesh against the facets themselves: every triangle names the facet's vertices (by key, position
// and attributes), and each vertex appears once. Point ids dense (a live map) and sparse (the index's hash
// fallback), with Steiner vertices among them.
TEST(FacetsToMesh, EveryTriangleNamesItsFacetsVerticesOnce) {
  for (const std::uint32_t id_stride : {1u, 100'000u}) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Delaunay dt;
    for (std::uint32_t i = 0; i < 400; ++i) {
      const VertexHandle v = dt.insert(Point(unit(rng), unit(rng), unit(rng)));
      const bool steiner = i % 10 == 0;
      v->info() = VertexInfo{steiner ? i : i * id_stride, steiner, false, 0, {}};
      if (!steiner) v->info().attributes = {Label(i % 7), {std::uint8_t(i), 2, 3}};
    }
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
      c->info().carved = unit(rng) < 0.4;
    std::vector<SurfaceFacet> facets;
    CollectSurface(dt, EmitRule{/*drop_steiner=*/false, /*drop_unseen=*/false}, &facets);
    ASSERT_GT(facets.size(), 100u);

    const Label unlabelled = 255;
    const IdentifiedMesh out = FacetsToMesh(facets, unlabelled);
    ASSERT_EQ(out.mesh.triangles.size(), facets.size());
    ASSERT_EQ(out.vertex_ids.size(), out.mesh.vertices.size());
    EXPECT_EQ(std::set<VertexId>(out.vertex_ids.begin(), out.vertex_ids.end()).size(), out.vertex_ids.size())
        << "a vertex appears twice";
    for (std::size_t t = 0; t < facets.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const VertexHandle v = facets[t].vertices[k];
        const std::uint32_t m = out.mesh.triangles[t][k];
        ASSERT_EQ(out.vertex_ids[m], VertexKey(v));
        EXPECT_EQ(out.mesh.vertices[m], ToEigen(v->point()));
        EXPECT_EQ(out.mesh.labels[m], v->info().steiner ? unlabelled : v->info().attributes.label);
        if (!v->info().steiner) {
          EXPECT_EQ(out.mesh.colors_rgb[m], v->info().attributes.color_rgb);
        }
      }
    }
  }
}

// OrientedFacet orders a facet by CGAL's vertex triple instead of testing its orientation: held against the
// test on every facet of a random triangulation, points on a grid among them (coplanar and cospherical
// quadruples, the degenerate cases of the predicates).
TEST(OrientedFacet, IsCounterClockwiseSeenFromTheCell) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Delaunay dt;
  for (int i = 0; i < 300; ++i) dt.insert(Point(unit(rng), unit(rng), unit(rng)));
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z) dt.insert(Point(2.0 + x, y, z));
  std::uint32_t id = 0;
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) v->info().id = id++;
  std::size_t checked = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    for (int i = 0; i < 4; ++i) {
      const SurfaceFacet f = OrientedFacet(c, i);
      ASSERT_EQ(CGAL::orientation(f.vertices[0]->point(), f.vertices[1]->point(), f.vertices[2]->point(),
                                  c->vertex(i)->point()),
                CGAL::POSITIVE);
      for (const VertexHandle v : f.vertices) EXPECT_NE(v, c->vertex(i));
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000u);
}

}  // namespace
}  // namespace semap::map_internal
