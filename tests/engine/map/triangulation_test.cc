#include "engine/map/internal/triangulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
#include <cstdint>
#include <iterator>
#include <random>
#include <set>
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
  EXPECT_GT(lower_address, 0)
      << "no new vertex reused a freed slot below an older one: the test shows nothing";
  // Cells are numbered the same way: those of the last insertion come after every cell before it.
  std::size_t newest_before = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c)
    newest_before = std::max(newest_before, c->time_stamp());
  const VertexHandle last = dt.insert(random_point());
  std::vector<CellHandle> star;
  dt.incident_cells(last, std::back_inserter(star));
  ASSERT_FALSE(star.empty());
  for (const CellHandle c : star) EXPECT_GT(c->time_stamp(), newest_before);
}

// The incremental map removes its moved and outlier vertices one at a time and marks the cells each removal
// hands over as created (DepthVoteMode::RemoveVertices). Removing neighbours one after the other destroys
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
    if (std::find(removed.begin(), removed.end(), vertices[i]) == removed.end())
      removed.push_back(vertices[i]);
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

// The incremental map finds each point's conflict region as it inserts the points, and leaves out a point
// whose region holds a pinned cell carved across a facet (DepthVoteMode::InsertInheriting). That
// relies on two facts checked here against a pass over the triangulation before any insertion: the points
// left out are those whose region in the old triangulation held such a cell, and the old cells destroyed are
// those in the old region of a point that went in.
TEST(Triangulation, ConflictsFoundWhileInsertingAreThoseOfTheOldTriangulation) {
  Delaunay dt;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> coordinate(0.0, 10.0);
  const auto random_point = [&] { return Point(coordinate(rng), coordinate(rng), coordinate(rng)); };
  for (int i = 0; i < 500; ++i) dt.insert(random_point());
  // Every 7th finite cell pinned and carved across a facet (sealed, keeping one carved facet).
  int n = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    if (n++ % 7 == 0) c->info().sealed = CellInfo::kSealed | 1;
  }
  const auto blocks = [](CellHandle c) { return IsPinned(c) && c->info().CarvedAcrossAny(); };
  std::vector<Point> pending;
  for (int i = 0; i < 300; ++i) pending.push_back(random_point());

  // The reference: each point's conflict region in the triangulation as it is now.
  constexpr std::uint32_t kOld = 1, kCreatedNow = 2;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) c->info().stamp = kOld;
  std::vector<bool> left_out_before(pending.size(), false);
  std::set<std::size_t> destroyed_before;  // old cells, by time stamp
  for (std::size_t k = 0; k < pending.size(); ++k) {
    std::vector<CellHandle> region;
    dt.find_conflicts(pending[k], dt.locate(pending[k]), CGAL::Emptyset_iterator(),
                      std::back_inserter(region));
    left_out_before[k] = std::any_of(region.begin(), region.end(), blocks);
    if (left_out_before[k]) continue;
    for (const CellHandle c : region) destroyed_before.insert(c->time_stamp());
  }
  ASSERT_GT(std::count(left_out_before.begin(), left_out_before.end(), true), 10);

  // While inserting, as the map does.
  std::vector<bool> left_out_while(pending.size(), false);
  std::set<std::size_t> destroyed_while;
  for (std::size_t k = 0; k < pending.size(); ++k) {
    std::vector<CellHandle> hole;
    std::vector<Delaunay::Facet> boundary;
    dt.find_conflicts(pending[k], dt.locate(pending[k]), std::back_inserter(boundary),
                      std::back_inserter(hole));
    if (std::any_of(hole.begin(), hole.end(), blocks)) {
      left_out_while[k] = true;
      continue;
    }
    for (const CellHandle c : hole) {
      if (c->info().stamp == kOld) destroyed_while.insert(c->time_stamp());
    }
    const VertexHandle v = dt.insert_in_hole(pending[k], hole.begin(), hole.end(), boundary.front().first,
                                             boundary.front().second);
    std::vector<CellHandle> star;
    dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) c->info().stamp = kCreatedNow;
  }
  EXPECT_EQ(left_out_while, left_out_before);
  EXPECT_EQ(destroyed_while, destroyed_before);
  // And the old cells still there are exactly the others.
  std::size_t old_left = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    if (c->info().stamp != kOld) continue;
    ++old_left;
    EXPECT_EQ(destroyed_before.count(c->time_stamp()), 0u);
  }
  EXPECT_GT(old_left, 0u);
  EXPECT_TRUE(dt.is_valid());
}

}  // namespace
}  // namespace semap::map_internal
