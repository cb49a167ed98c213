#include "tests/engine/map/manifold_checker.h"

#include <gtest/gtest.h>

namespace semap::test {
namespace {

Mesh Tetrahedron() {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

TEST(ManifoldChecker, AcceptsAClosedTetrahedron) {
  const auto r = CheckManifold(Tetrahedron(), false);
  EXPECT_TRUE(r.ok()) << r.Summary();
  EXPECT_EQ(r.num_boundary_edges, 0u);
}

TEST(ManifoldChecker, RejectsAFlippedTriangle) {
  Mesh m = Tetrahedron();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  EXPECT_FALSE(CheckManifold(m, false).ok());
}

TEST(ManifoldChecker, OpenSurfaceNeedsBoundaryAllowed) {
  Mesh m = Tetrahedron();
  m.triangles.pop_back();
  EXPECT_FALSE(CheckManifold(m, false).ok());
  const auto r = CheckManifold(m, true);
  EXPECT_TRUE(r.ok()) << r.Summary();
  EXPECT_EQ(r.num_boundary_edges, 3u);
}

TEST(ManifoldChecker, RejectsTwoTetrahedraSharingAVertex) {
  Mesh m = Tetrahedron();
  const Mesh t = Tetrahedron();
  for (int k = 1; k < 4; ++k) m.vertices.push_back(-t.vertices[k]);
  // Mirror copy through vertex 0 (mirroring flips orientation, so reverse each triangle).
  auto map = [](std::uint32_t i) { return i == 0 ? 0u : i + 3; };
  for (const auto& tri : t.triangles) m.triangles.push_back({map(tri[0]), map(tri[2]), map(tri[1])});
  const auto r = CheckManifold(m, false);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.Summary().find("vertex 0"), std::string::npos) << r.Summary();
}

TEST(ManifoldChecker, RejectsDegenerateAndDuplicateTriangles) {
  Mesh m = Tetrahedron();
  m.triangles.push_back({0, 0, 1});
  EXPECT_FALSE(CheckManifold(m, false).ok());
  m = Tetrahedron();
  m.triangles.push_back({1, 3, 2});
  EXPECT_FALSE(CheckManifold(m, false).ok());
  m = Tetrahedron();
  m.vertices[3] = {1, 1, 0};  // all four coplanar: zero-area... not necessarily; make one collinear
  m.vertices[3] = {2, 0, 0};
  EXPECT_FALSE(CheckManifold(m, false).ok());
}

}  // namespace
}  // namespace semap::test
