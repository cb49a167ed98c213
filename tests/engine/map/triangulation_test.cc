#include "engine/map/internal/triangulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
#include <cstdint>
#include <iterator>
#include <random>
#include <vector>

namespace semap::map_internal {
namespace {

// CGAL orders handles (operator<) inside its algorithms, e.g. vertex removal walks a std::map of the hole's
// facets keyed by vertex handles. The map's vertices and cells carry a time stamp, so that order is the order
// of creation, whatever addresses the allocator handed out: a vertex created after a removal reuses the freed
// slot, at a lower address than older vertices, and must still compare greater than all of them.
TEST(Triangulation, HandlesCompareByCreationNotByAddress) {
  static_assert(CGAL::internal::Has_timestamp<Tds::Vertex>::value, "vertices without a time stamp");
  static_assert(CGAL::internal::Has_timestamp<Tds::Cell>::value, "cells without a time stamp");
  Delaunay dt;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(0.0, 10.0);
  const auto random_point = [&] { return Point(coordinate(rng), coordinate(rng), coordinate(rng)); };
  std::vector<VertexHandle> created;
  for (int i = 0; i < 200; ++i) created.push_back(dt.insert(random_point()));
  // Free the slots of the first half; the next insertions take them (Compact_container's free list).
  for (int i = 0; i < 100; ++i) dt.remove(created[i]);
  created.erase(created.begin(), created.begin() + 100);
  int lower_address = 0;
  for (int i = 0; i < 50; ++i) {
    const VertexHandle fresh = dt.insert(random_point());
    for (const VertexHandle older : created) {
      ASSERT_TRUE(older < fresh) << "a vertex created later compares lower";
      if (&*fresh < &*older) ++lower_address;
    }
    created.push_back(fresh);
  }
  // The case the time stamp is for: without it, these pairs would compare the other way.
  EXPECT_GT(lower_address, 0) << "no new vertex reused a freed slot below an older one: the test shows nothing";
  // Cells are numbered the same way: those of the last insertion come after every cell before it.
  std::size_t newest_before = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) newest_before = std::max(newest_before, c->time_stamp());
  const VertexHandle last = dt.insert(random_point());
  std::vector<CellHandle> star;
  dt.incident_cells(last, std::back_inserter(star));
  ASSERT_FALSE(star.empty());
  for (const CellHandle c : star) EXPECT_GT(c->time_stamp(), newest_before);
}

// The incremental map removes its moved and outlier vertices one at a time and marks the cells each removal
// hands over as created (IncrementalState::RemoveRefined). Removing neighbours one after the other destroys
// cells an earlier removal created, and new cells may reuse their slots: the marks must still fall on exactly
// the cells that were not there before, as a stamp of every old cell tells.
TEST(Triangulation, CellsGivenByOneRemovalAfterAnotherAreExactlyTheNewCells) {
  Delaunay dt;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> coordinate(0.0, 10.0);
  std::vector<VertexHandle> vertices;
  for (int i = 0; i < 400; ++i) {
    vertices.push_back(dt.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng))));
  }
  constexpr std::uint32_t kOld = 1, kCreated = 2;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) c->info().stamp = kOld;
  // A vertex and its neighbours (their holes overlap), then scattered ones.
  std::vector<VertexHandle> removed{vertices[7]};
  dt.finite_adjacent_vertices(vertices[7], std::back_inserter(removed));
  for (int i = 100; i < 400; i += 37) {
    if (std::find(removed.begin(), removed.end(), vertices[i]) == removed.end()) removed.push_back(vertices[i]);
  }
  ASSERT_GT(removed.size(), 10u);
  const auto mark_created =
      boost::make_function_output_iterator([](CellHandle c) { c->info().created = kCreated; });
  for (const VertexHandle v : removed) dt.remove_and_give_new_cells(v, mark_created);
  ASSERT_TRUE(dt.is_valid());
  int new_cells = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    const bool is_new = c->info().stamp != kOld;
    new_cells += is_new;
    EXPECT_EQ(c->info().created == kCreated, is_new);
  }
  EXPECT_GT(new_cells, 0);
}

}  // namespace
}  // namespace semap::map_internal
