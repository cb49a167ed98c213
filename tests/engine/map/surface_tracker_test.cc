#include "engine/map/internal/surface_tracker.h"

#include <gtest/gtest.h>

#include <iterator>
#include <random>
#include <set>

#include "engine/map/internal/manifold_carver.h"

namespace semap::map_internal {
namespace {

using TriangleKey = std::array<VertexId, 3>;

// The reference: the surface read out of the whole triangulation, as canonical oriented triangles.
std::set<TriangleKey> ReferenceSurface(const Delaunay& dt, bool drop_steiner) {
  std::vector<SurfaceFacet> facets;
  CollectSurface(dt, drop_steiner, &facets);
  std::set<TriangleKey> out;
  for (const SurfaceFacet& f : facets) {
    out.insert(CanonicalTriangle({VertexKey(f.vertices[0]), VertexKey(f.vertices[1]), VertexKey(f.vertices[2])}));
  }
  return out;
}

// What a subscriber of the changes holds: the changes applied in order.
void Apply(const SurfaceChange& change, std::set<TriangleKey>* surface) {
  for (const TriangleKey& t : change.removed) {
    EXPECT_EQ(surface->erase(t), 1u) << "a triangle removed that was not there";
  }
  for (const auto& t : change.added.mesh.triangles) {
    const auto& ids = change.added.vertex_ids;
    EXPECT_TRUE(surface->insert(CanonicalTriangle({ids[t[0]], ids[t[1]], ids[t[2]]})).second)
        << "a triangle added that was there";
  }
}

PointAttributes NoAttributes(std::uint32_t) { return {}; }

class SurfaceTrackerTest : public ::testing::TestWithParam<bool> {};

// Random carving, uncarving and insertions (which destroy and create cells) on a random triangulation: after
// every step the tracked surface, and the surface rebuilt from the changes it reported, equal the surface
// read out of the whole triangulation. With drop_steiner, every fifth vertex is a Steiner vertex.
TEST_P(SurfaceTrackerTest, EqualsTheWholeSurfaceAfterEveryChange) {
  const bool drop_steiner = GetParam();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Delaunay dt;
  std::uint32_t next_id = 0;
  auto insert = [&](const Point& p) {
    const VertexHandle v = dt.insert(p);
    v->info() = VertexInfo{next_id, drop_steiner && next_id % 5 == 0, 0};
    ++next_id;
    return v;
  };
  for (int i = 0; i < 800; ++i) insert(Point(unit(rng), unit(rng), unit(rng)));

  SurfaceTracker tracker(&dt, drop_steiner);
  ManifoldCarver carver(&dt, 3);
  carver.set_journal(tracker.dirty());
  std::set<TriangleKey> rebuilt;
  std::size_t max_size = 0;
  auto check = [&](const std::string& step) {
    tracker.Sync();
    const std::set<TriangleKey> expected = ReferenceSurface(dt, drop_steiner);
    EXPECT_EQ(tracker.size(), expected.size()) << step;
    Apply(tracker.Take(NoAttributes, 0), &rebuilt);
    EXPECT_TRUE(rebuilt == expected) << step << ": " << rebuilt.size() << " rebuilt vs " << expected.size();
    max_size = std::max(max_size, expected.size());
  };

  for (int round = 0; round < 12; ++round) {
    const std::string step = "round " + std::to_string(round);
    // Carve (through the carver, which journals) a random batch of cells.
    std::vector<CellHandle> cells;
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) cells.push_back(c);
    std::shuffle(cells.begin(), cells.end(), rng);
    for (std::size_t i = 0; i < cells.size() / 6; ++i) carver.TryCarve(cells[i]);
    check(step + ", carved");
    // Uncarve the stars of a few vertices.
    std::vector<VertexHandle> vertices;
    for (int k = 0; k < 5; ++k) vertices.push_back(cells[rng() % cells.size()]->vertex(int(rng() % 4)));
    std::vector<CellHandle> uncarved;
    carver.UncarveStars(vertices, &uncarved);
    check(step + ", uncarved");
    // Insert points: forget the cells they destroy, list the cells they create.
    for (int k = 0; k < 20; ++k) {
      const Point p(unit(rng), unit(rng), unit(rng));
      std::vector<CellHandle> doomed;
      dt.find_conflicts(p, dt.locate(p), CGAL::Emptyset_iterator(), std::back_inserter(doomed));
      tracker.Sync();
      tracker.Forget(doomed);
      const VertexHandle v = insert(p);
      dt.incident_cells(v, std::back_inserter(*tracker.created()));
    }
    check(step + ", inserted");
    if (HasFailure()) return;
  }
  EXPECT_GT(max_size, 500u) << "the test carved too little to mean anything";
}

INSTANTIATE_TEST_SUITE_P(SteinerKeptAndDropped, SurfaceTrackerTest, ::testing::Bool());

}  // namespace
}  // namespace semap::map_internal
