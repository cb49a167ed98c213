// The finaliser's cut against the surface read off before and after (CollectSurface): the surface that stays
// live does not change.
#include "engine/map/internal/hole_cut.h"

#include <gtest/gtest.h>

#include <set>

#include "engine/core/mesh_delta.h"
#include "engine/map/internal/surface_extraction.h"
#include "tests/engine/map/carved_cloud.h"

namespace semap::map_internal {
namespace {

// The surface facets by their vertex keys, in their orientation (rotated to start at the smallest key).
std::set<std::array<VertexId, 3>> OrientedSurface(const Delaunay& dt) {
  std::vector<SurfaceFacet> facets;
  CollectSurface(dt, EmitRule{/*drop_steiner=*/false, /*drop_unseen=*/false}, &facets);
  std::set<std::array<VertexId, 3>> out;
  for (const SurfaceFacet& f : facets) {
    out.insert(
        CanonicalTriangle({VertexKey(f.vertices[0]), VertexKey(f.vertices[1]), VertexKey(f.vertices[2])}));
  }
  return out;
}

// Vertices in a ball around a point of the surface are removed: their stars go, the hole is re-triangulated
// and sealed with the sides recorded before. Afterwards the surface is the one before less the facets inside
// the hole (both cells destroyed: what finalisation emits), each of the others with its orientation; the
// hole's boundary facets kept carved behind them by the seal are among those. The seam holds the staying
// vertices of the hole's surface facets.
TEST(HoleCut, KeepsTheSurfaceThatStays) {
  Delaunay dt;
  test::CarveHalfCloud(&dt);
  const auto before = OrientedSurface(dt);
  constexpr std::uint32_t kRemoved = 3, kDestroyed = 5, kSeam = 7, kOld = 9, kCreated = 11;
  const std::vector<VertexHandle> removed = test::VerticesNear(dt, Eigen::Vector3d(5.0, 5.0, 5.0), 2.0);
  ASSERT_GT(removed.size(), 20u);
  for (const VertexHandle v : removed) v->info().stamp = kRemoved;
  const std::vector<CellHandle> destroyed = test::StarsOf(dt, removed, kDestroyed);
  std::set<std::array<VertexId, 3>> inside;  // surface facets with both cells destroyed
  std::set<const void*> seam_expected;
  std::vector<VertexHandle> boundary;
  std::set<const void*> in_boundary;
  for (const CellHandle d : destroyed) {
    for (int i = 0; i < 4; ++i) {
      const VertexHandle v = d->vertex(i);
      if (!dt.is_infinite(v) && v->info().stamp != kRemoved && in_boundary.insert(&*v).second)
        boundary.push_back(v);
      if (dt.is_infinite(d) || !TakenFrom(dt, d, i)) continue;
      const SurfaceFacet f = OrientedSurfaceFacet(d, i);
      if (d->neighbor(i)->info().stamp == kDestroyed) {
        inside.insert(CanonicalTriangle(
            {VertexKey(f.vertices[0]), VertexKey(f.vertices[1]), VertexKey(f.vertices[2])}));
      }
      for (const VertexHandle u : f.vertices) {
        if (u->info().stamp != kRemoved) seam_expected.insert(&*u);
      }
    }
  }
  ASSERT_GT(inside.size(), 20u);

  const std::vector<VertexHandle> seam = HoleSeam(dt, destroyed, kDestroyed, kRemoved, kSeam);
  std::set<const void*> seam_set;
  for (const VertexHandle v : seam) seam_set.insert(&*v);
  EXPECT_EQ(seam_set.size(), seam.size()) << "a seam vertex listed twice";
  EXPECT_TRUE(std::includes(seam_set.begin(), seam_set.end(), seam_expected.begin(), seam_expected.end()));
  const HoleSides sides = RecordHoleSides(destroyed, kDestroyed);
  std::vector<CellHandle> star;
  for (const VertexHandle v : boundary) {
    star.clear();
    dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) c->info().stamp = kOld;
  }
  dt.remove_cluster(removed.begin(), removed.end());
  std::size_t refill = 0;
  for (const VertexHandle v : boundary) {
    star.clear();
    dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == kOld || c->info().created == kCreated) continue;
      c->info().created = kCreated;
      ++refill;
    }
  }
  ASSERT_GT(refill, 20u);
  SealHole(&dt, boundary, kCreated, sides);

  std::set<std::array<VertexId, 3>> expected;
  std::set_difference(before.begin(), before.end(), inside.begin(), inside.end(),
                      std::inserter(expected, expected.end()));
  EXPECT_EQ(OrientedSurface(dt), expected);
  EXPECT_LT(expected.size(), before.size());
}

}  // namespace
}  // namespace semap::map_internal
