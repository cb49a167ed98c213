// The mesher against the surface read off the triangulation directly (CollectSurface, FacetsToMesh).
#include "engine/map/internal/mesher.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "engine/map/internal/hole_cut.h"
#include "tests/engine/map/carved_cloud.h"

namespace semap::map_internal {
namespace {

using KeyTriangles = std::multiset<std::array<VertexId, 3>>;

// A mesh's triangles by vertex ids, each rotated to start at its smallest id (orientation kept).
KeyTriangles ByIds(const IdentifiedMesh& m) {
  KeyTriangles out;
  for (const auto& t : m.mesh.triangles) {
    out.insert(CanonicalTriangle({m.vertex_ids[t[0]], m.vertex_ids[t[1]], m.vertex_ids[t[2]]}));
  }
  return out;
}

class MesherTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test::CarveHalfCloud(&dt_);
    ASSERT_GT(CountCarvedCells(dt_), 1000u);
  }

  Delaunay dt_;
  const EmitRule rule_{/*drop_steiner=*/true, /*drop_unseen=*/false};
};

TEST_F(MesherTest, LiveMeshIsTheWholeSurface) {
  const Mesher mesher(&dt_, rule_);
  std::vector<SurfaceFacet> facets;
  CollectSurface(dt_, rule_, &facets);
  const IdentifiedMesh live = mesher.ExtractLive();
  EXPECT_EQ(ByIds(live), ByIds(FacetsToMesh(facets, 0)));
  EXPECT_GT(live.mesh.num_triangles(), 300u);  // 488: the plane x = 5 and the hull around the free side
}

// A hole about to be cut (the stars of a few vertices): the finalised triangles are the surface facets with
// both cells in the hole, each once and oriented as on the surface, with the vertices' ids; taking them
// empties the mesher.
TEST_F(MesherTest, EmitsTheSurfaceInsideAHoleOnce) {
  Mesher mesher(&dt_, rule_);
  const std::vector<VertexHandle> removed = test::VerticesNear(dt_, Eigen::Vector3d(5.0, 5.0, 5.0), 2.0);
  ASSERT_GT(removed.size(), 20u);
  constexpr std::uint32_t kRemoved = 3, kDestroyed = 5, kSeam = 7;
  for (const VertexHandle v : removed) v->info().stamp = kRemoved;
  const std::vector<CellHandle> destroyed = test::StarsOf(dt_, removed, kDestroyed);
  // The seam as the finaliser gives it (HoleSeam, tested in hole_cut_test.cc): an input here.
  const std::vector<VertexHandle> seam = HoleSeam(dt_, destroyed, kDestroyed, kRemoved, kSeam);
  std::vector<SurfaceFacet> facets;
  CollectSurface(dt_, rule_, &facets);
  std::vector<SurfaceFacet> inside;  // the reference: both cells of the facet destroyed
  for (const SurfaceFacet& f : facets) {
    Delaunay::Cell_handle c;
    int i, j, k;
    ASSERT_TRUE(dt_.is_facet(f.vertices[0], f.vertices[1], f.vertices[2], c, i, j, k));
    const int opposite = 6 - i - j - k;
    if (c->info().stamp == kDestroyed && c->neighbor(opposite)->info().stamp == kDestroyed)
      inside.push_back(f);
  }
  ASSERT_GT(inside.size(), 20u);

  mesher.EmitHole(destroyed, kDestroyed, removed, seam);
  const IdentifiedMesh finalised = mesher.TakeFinalised();
  EXPECT_EQ(ByIds(finalised), ByIds(FacetsToMesh(inside, 0)));
  EXPECT_EQ(finalised.vertex_ids.size(), finalised.mesh.vertices.size());
  EXPECT_EQ(mesher.TakeFinalised().mesh.num_triangles(), 0u);
}

}  // namespace
}  // namespace semap::map_internal
