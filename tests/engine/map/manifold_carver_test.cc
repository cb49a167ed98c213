#include "engine/map/internal/manifold_carver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace semap::map_internal {
namespace {

// The reference carve test: carve the cell, then run the full link test at its four vertices.
bool ReferenceCarvable(ManifoldCarver& carver, CellHandle cell) {
  cell->info().carved = true;
  bool regular = true;
  for (int k = 0; k < 4 && regular; ++k) regular = carver.IsRegular(cell->vertex(k));
  cell->info().carved = false;
  return regular;
}

// TryCarve decides most cases from the cells around the carved cell (a case analysis of the vertex links);
// it must agree with the full link test in every case, from random carving orders (disconnected pieces,
// pinches, filled holes) and after local uncarving.
TEST(ManifoldCarver, LocalCarveTestEqualsFullLinkTest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Delaunay dt;
  for (int i = 0; i < 1500; ++i) dt.insert(Point(unit(rng), unit(rng), unit(rng)));
  std::vector<CellHandle> cells;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) cells.push_back(c);
  ManifoldCarver carver(&dt, 3);
  std::size_t carved = 0, refused = 0;
  auto check = [&](CellHandle c, int round) {
    const bool expected = ReferenceCarvable(carver, c);
    EXPECT_EQ(carver.TryCarve(c), expected) << "round " << round;
    ++(expected ? carved : refused);
    return expected;
  };
  for (int round = 0; round < 8; ++round) {
    if (round % 2 == 0) {
      // Random order over all cells: scattered pieces.
      std::shuffle(cells.begin(), cells.end(), rng);
      for (const CellHandle c : cells) {
        if (!c->info().carved) check(c, round);
      }
    } else {
      // Growth of one region from a random cell of an empty carving: tunnels and pinches along a region.
      for (const CellHandle c : cells) c->info().carved = false;
      std::vector<CellHandle> frontier{cells[rng() % cells.size()]};
      while (!frontier.empty()) {
        // Rounds 1 and 5 pick at random, rounds 3 and 7 the cell with most carved neighbours (as Grow).
        std::size_t pick = rng() % frontier.size();
        if (round % 4 == 3) {
          auto carved_neighbours = [](CellHandle c) {
            int n = 0;
            for (int i = 0; i < 4; ++i) n += c->neighbor(i)->info().carved ? 1 : 0;
            return n;
          };
          for (std::size_t i = 0; i < frontier.size(); ++i) {
            if (carved_neighbours(frontier[i]) > carved_neighbours(frontier[pick])) pick = i;
          }
        }
        std::swap(frontier[pick], frontier.back());
        const CellHandle c = frontier.back();
        frontier.pop_back();
        if (c->info().carved || dt.is_infinite(c) || !check(c, round)) continue;
        for (int i = 0; i < 4; ++i) frontier.push_back(c->neighbor(i));
      }
    }
    // Reopen a few regions (every vertex stays regular: the carver's invariant).
    std::vector<VertexHandle> centres;
    for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
      if (unit(rng) < 0.1) centres.push_back(v);
    }
    std::vector<CellHandle> uncarved;
    carver.UncarveStars(centres, &uncarved);
    EXPECT_FALSE(uncarved.empty());
  }
  EXPECT_GT(carved, 100u);
  EXPECT_GT(refused, 100u);
}

}  // namespace
}  // namespace semap::map_internal
