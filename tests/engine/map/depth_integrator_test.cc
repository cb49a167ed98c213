// The depth integrator against a simple reference: every cell voted by each view of the window, one cell and
// one view at a time (VoteCell, SeenFacets), without walks, blocks, spatial orders or threads; the surface
// facets looked for in the seen window's views, one facet and one view at a time.
#include "engine/map/internal/depth_integrator.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "engine/map/internal/surface_extraction.h"
#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

constexpr int kWidthPx = 160;
constexpr int kHeightPx = 120;
constexpr double kFocalPx = 100.0;

// A view from `world_from_cam` with depths at random (with holes and sky).
std::shared_ptr<const DepthView> RandomView(const Eigen::Isometry3d& world_from_cam, std::mt19937* rng) {
  auto view = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  std::uniform_real_distribution<float> depth_m(1.0f, 30.0f), unit(0.0f, 1.0f);
  for (int v = 0; v < kHeightPx; ++v) {
    for (int u = 0; u < kWidthPx; ++u) {
      const float r = unit(*rng);
      view->depth_m.at<float>(v, u) = r < 0.1f ? 0.0f : r < 0.15f ? kFreeToFarRange : depth_m(*rng);
    }
  }
  view->world_from_cam = world_from_cam;
  return view;
}

std::array<Eigen::Vector3d, 4> Vertices(CellHandle c) {
  std::array<Eigen::Vector3d, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = ToEigen(c->vertex(k)->point());
  return v;
}

struct Votes {
  std::int64_t free_q = 0, matter_q = 0;
  bool operator==(const Votes&) const = default;
};

class DepthIntegratorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    options_.vote_window_frames = 2;
    options_.disparity_sigma_px = 0.0;
    std::uniform_real_distribution<double> coordinate(-30.0, 30.0);
    for (int i = 0; i < 3000; ++i) dt_.insert(Point(coordinate(rng_), coordinate(rng_), coordinate(rng_)));
    for (int f = 0; f < 3; ++f) {  // three frames, the window keeps the last two
      views_.push_back(RandomView(Eigen::Translation3d(2.0 * f, -1.0, 0.5 * f) *
                                      Eigen::AngleAxisd(0.3 * f, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()),
                                  &rng_));
    }
  }

  // Every finite cell holds the votes `expected` gives it and each facet's seen state is `expected_seen`'s;
  // returns the number of (cell, facet) pairs seen.
  std::size_t ExpectCells(const std::map<CellHandle, Votes>& expected,
                          const std::map<FacetHandles, bool>& expected_seen) const {
    std::size_t seen_facets = 0;
    for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
      EXPECT_EQ((Votes{c->info().free_q, c->info().matter_q}), expected.at(c));
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(FacetSeen(c, k), expected_seen.at(SortedFacet(c, k)));
        seen_facets += FacetSeen(c, k) ? 1 : 0;
      }
    }
    return seen_facets;
  }

  MapOptions options_;
  std::mt19937 rng_{23};
  Delaunay dt_;
  std::vector<std::shared_ptr<const DepthView>> views_;
};

// The cells an update created get the votes of every view of the window instead of what they inherited (kept
// where no view votes), each created cell is listed touched, in creation order, and no facet of a created
// cell is looked for yet (that is MarkSeenSurface's, after the carving).
TEST_F(DepthIntegratorTest, CreatedCellsGetTheWindowsVotes) {
  DepthIntegrator integrator(&dt_, options_);
  for (const auto& view : views_) integrator.AddFrame({view});
  ASSERT_EQ(integrator.views().size(), 2u);
  const DepthVoteGeometry geometry(options_);
  const std::vector<VotingView> window{VotingView(views_[1]), VotingView(views_[2])};

  constexpr std::uint32_t kCreated = 7;
  std::uniform_int_distribution<std::int64_t> inherited(0, 1000);
  std::vector<CellHandle> created;
  std::map<CellHandle, Votes> expected;
  std::map<FacetHandles, bool> expected_seen;
  std::size_t expected_voted = 0;
  for (auto c = dt_.all_cells_begin(); c != dt_.all_cells_end(); ++c) {
    c->info().created = kCreated;
    created.push_back(c);
  }
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    c->info().free_q = inherited(rng_);
    c->info().matter_q = inherited(rng_);
    Votes fresh;
    for (const VotingView& view : window) {
      const VoteIncrement v = VoteCell(Vertices(c), view, geometry);
      fresh.free_q += v.free_q;
      fresh.matter_q += v.matter_q;
    }
    const Votes before{c->info().free_q, c->info().matter_q};
    expected[c] = fresh == Votes{} ? before : fresh;
    expected_voted += expected[c] == before ? 0 : 1;  // a vote: what the cell holds changed
    for (int k = 0; k < 4; ++k) expected_seen[SortedFacet(c, k)] = false;
  }

  std::vector<CellHandle> touched, newly_seen;
  const std::size_t voted =
      integrator.Integrate(created, {kCreated, /*touch=*/11, /*visit=*/13}, &touched, &newly_seen);
  EXPECT_EQ(ExpectCells(expected, expected_seen), 0u);
  EXPECT_EQ(voted, expected_voted);
  EXPECT_GT(voted, 1000u);
  ASSERT_EQ(touched.size(), expected.size()) << "every created cell is touched";
  for (std::size_t i = 1; i < touched.size(); ++i)
    EXPECT_LT(touched[i - 1]->time_stamp(), touched[i]->time_stamp());
  EXPECT_TRUE(newly_seen.empty());
}

// After the carving: every surface facet (carved on one side only) of the listed cells that some view of the
// seen window sees is marked seen, here a window one frame longer than the vote window's, so that the view
// that left the votes still looks; no other facet is marked, and the cells marked from are listed, in
// creation order. Facets already seen stay seen and facets of cells not listed are not looked at.
TEST_F(DepthIntegratorTest, SurfaceFacetsAreLookedForInTheSeenWindow) {
  options_.seen_window_frames = 3;
  DepthIntegrator integrator(&dt_, options_);
  for (const auto& view : views_) integrator.AddFrame({view});
  ASSERT_EQ(integrator.views().size(), 2u) << "the vote window";
  const DepthVoteGeometry geometry(options_);
  std::vector<VotingView> seen_window;
  for (const auto& view : views_) seen_window.emplace_back(view);

  std::bernoulli_distribution carve(0.5), listed(0.8);
  std::vector<CellHandle> cells;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    c->info().carved = carve(rng_);
    if (listed(rng_)) cells.push_back(c);
  }
  std::set<CellHandle> in_list(cells.begin(), cells.end());
  std::map<FacetHandles, bool> expected_seen;
  std::size_t surface_facets = 0, seen_only_by_the_oldest_view = 0;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    for (int k = 0; k < 4; ++k) {
      const FacetHandles f = SortedFacet(c, k);
      const CellHandle n = c->neighbor(k);
      const bool surface = c->info().carved != n->info().carved;
      if (!surface || (!in_list.count(c) && (dt_.is_infinite(n) || !in_list.count(n)))) {
        expected_seen.emplace(f, false);
        continue;
      }
      ++surface_facets;
      bool seen = false, seen_by_newer = false;
      for (std::size_t w = 0; w < seen_window.size(); ++w) {
        const bool here = SeenFacets(Vertices(c), 1u << k, seen_window[w], geometry) != 0;
        seen = seen || here;
        if (w > 0) seen_by_newer = seen_by_newer || here;
      }
      expected_seen[f] = seen;
      seen_only_by_the_oldest_view += seen && !seen_by_newer ? 1 : 0;
    }
  }
  std::vector<CellHandle> newly_seen;
  const std::size_t marked = integrator.MarkSeenSurface(cells, /*list_mark=*/17, &newly_seen);
  std::map<CellHandle, Votes> votes;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) votes[c] = {0, 0};
  const std::size_t seen_facets = ExpectCells(votes, expected_seen);
  EXPECT_GT(surface_facets, 1000u);
  EXPECT_GT(seen_facets, 100u);
  EXPECT_GT(seen_only_by_the_oldest_view, 0u)
      << "the test does not tell the seen window from the vote window";
  EXPECT_EQ(2 * marked, seen_facets) << "each marked facet counted from both its cells";
  for (std::size_t i = 1; i < newly_seen.size(); ++i)
    EXPECT_LT(newly_seen[i - 1]->time_stamp(), newly_seen[i]->time_stamp());
  for (const CellHandle c : newly_seen) EXPECT_NE(c->info().seen_facets, 0);
  // Once seen, a facet is not looked for again: a second pass marks nothing.
  std::vector<CellHandle> again;
  EXPECT_EQ(integrator.MarkSeenSurface(cells, /*list_mark=*/19, &again), 0u);
  EXPECT_TRUE(again.empty());
}

// An update that created nothing: the old cells get the newest view's votes added (every cell it votes is
// found by the walk), the carved ones have their surface facets the newest view sees marked, and the cells
// that changed sides, or are free and uncarved with a vote, are listed touched.
TEST_F(DepthIntegratorTest, OldCellsGetTheNewestViewsVotes) {
  DepthIntegrator integrator(&dt_, options_);
  for (const auto& view : views_) integrator.AddFrame({view});
  const DepthVoteGeometry geometry(options_);
  const VotingView newest(views_[2]);
  std::uniform_int_distribution<std::int64_t> earlier(0, 3000);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    c->info().free_q = earlier(rng_);
    c->info().matter_q = earlier(rng_);
    c->info().carved = unit(rng_) < 0.3;
  }
  std::map<CellHandle, Votes> expected;
  std::set<CellHandle> expected_touched;
  std::map<FacetHandles, bool> expected_seen;
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    const VoteIncrement v = VoteCell(Vertices(c), newest, geometry);
    const Votes after{c->info().free_q + v.free_q, c->info().matter_q + v.matter_q};
    expected[c] = after;
    const bool was_free = c->info().IsFree(), free = after.free_q > after.matter_q;
    const bool has_vote = v.free_q != 0 || v.matter_q != 0;
    if (was_free != free || (free && !c->info().carved && has_vote)) expected_touched.insert(c);
    for (int k = 0; k < 4; ++k) {
      bool& seen = expected_seen[SortedFacet(c, k)];
      if (c->info().carved && v.in_view && !NeighbourCarved(c, k)) {
        seen = seen || (SeenFacets(Vertices(c), 1u << k, newest, geometry) != 0);
      }
    }
  }

  std::vector<CellHandle> touched, newly_seen;
  integrator.Integrate({}, {/*created=*/7, /*touch=*/11, /*visit=*/13}, &touched, &newly_seen);
  const std::size_t seen_facets = ExpectCells(expected, expected_seen);
  EXPECT_GT(seen_facets, 10u);
  EXPECT_EQ(std::set<CellHandle>(touched.begin(), touched.end()), expected_touched);
  EXPECT_GT(expected_touched.size(), 100u);
  EXPECT_FALSE(newly_seen.empty());
}

}  // namespace
}  // namespace semap::map_internal
