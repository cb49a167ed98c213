// The two vote modes through their interface (VoteMode), each on a tiny scene, against a reference computed
// apart: for the rays, every cell's votes summed from the exact walk of each live ray on the triangulation as
// it stands (no retrace bookkeeping); for the depth maps, every cell's votes from the window's views one cell
// and one view at a time (VoteCell), and the points of a view seen again merged into the vertices they made.
#include "engine/map/internal/vote_mode.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <utility>

#include "engine/map/internal/depth_vote_mode.h"
#include "engine/map/internal/depth_votes.h"
#include "engine/map/internal/ray_tracer.h"
#include "engine/map/internal/ray_vote_mode.h"
#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

using CellVoteMap = std::map<const void*, std::pair<std::int64_t, std::int64_t>>;

// A map's parts as IncrementalMap::Impl holds them.
struct Parts {
  explicit Parts(const MapOptions& options)
      : state(options, OutputRule(options)), carver(state), votes(MakeVoteMode(state, carver)) {}
  MapState state;
  RegionCarver carver;
  std::unique_ptr<VoteMode> votes;
};

// The steps of a frame's update up to its votes, in the order IncrementalMap::Impl runs them.
MapUpdateResult LocateInsertVote(Parts* parts, const LabelledCloud& frame,
                                 const std::vector<Observation>& extra = {}) {
  MapUpdateResult result;
  parts->votes->CheckInput(frame, extra);
  parts->state.BeginFrame(frame);
  std::vector<PendingVertex> pending = parts->votes->Locate(frame, extra, &result);
  parts->votes->Insert(&pending, &result);
  parts->votes->Vote(&result);
  return result;
}

std::array<Eigen::Vector3d, 4> Vertices(CellHandle c) {
  std::array<Eigen::Vector3d, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = ToEigen(c->vertex(k)->point());
  return v;
}

CellVoteMap VotesOf(const Delaunay& dt) {
  CellVoteMap votes;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    votes[&*c] = {c->info().free_q, c->info().matter_q};
  }
  return votes;
}

// The finite cells whose votes differ from `expected`; a cell it does not name expects none, or is not
// checked.
int CellsDiffering(const Delaunay& dt, const CellVoteMap& expected, bool unnamed_expect_none = true) {
  int differing = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    const auto it = expected.find(&*c);
    if (it == expected.end() && !unnamed_expect_none) continue;
    const auto want = it == expected.end() ? std::pair<std::int64_t, std::int64_t>{} : it->second;
    if (c->info().free_q != want.first || c->info().matter_q != want.second) ++differing;
  }
  return differing;
}

TEST(VoteMode, MapVisibilityNamesTheModeAndOnlyDepthViewsDropUnseenSurface) {
  MapOptions depth;
  MapOptions rays;
  rays.visibility = Visibility::kRays;
  Parts depth_parts(depth), ray_parts(rays);
  EXPECT_NE(dynamic_cast<DepthVoteMode*>(depth_parts.votes.get()), nullptr);
  EXPECT_NE(dynamic_cast<RayVoteMode*>(ray_parts.votes.get()), nullptr);
  EXPECT_TRUE(OutputRule(depth).drop_unseen);
  EXPECT_FALSE(OutputRule(rays).drop_unseen);
  EXPECT_TRUE(OutputRule(rays).drop_steiner);
  depth.drop_unseen_surface = false;
  EXPECT_FALSE(OutputRule(depth).drop_unseen);
}

// ---- Rays ----

// A wall of 7 × 4 points at y = 6 seen from `camera`, shifted by `offset` along it.
LabelledCloud WallPoints(const Eigen::Vector3d& camera, double offset) {
  LabelledCloud frame;
  frame.camera_centers_world = {camera};
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 4; ++j) {
      frame.positions_world.push_back(
          {-3.0 + i + offset, 6.0 + 0.1 * ((i + j) % 3), 0.75 * j + 0.3 * offset});
      frame.camera_index.push_back(0);
    }
  }
  return frame;
}

// Every finite cell's votes summed from the exact walk of each live ray (the snapshot's first and extra
// rays) on today's triangulation.
CellVoteMap WalkedVotes(const MapState& state, const MapSnapshot& snapshot) {
  const RayGeometry geometry(state.options);
  CellVoteMap votes;
  const auto walk = [&](std::uint32_t point_index, std::uint32_t camera_index) {
    const VertexHandle v = state.points.at(snapshot.point_ids[point_index]).vertex;
    RayVotes ray;
    ASSERT_TRUE(
        ComputeRayVotes(state.dt, v, snapshot.cloud.camera_centers_world[camera_index], geometry, &ray));
    for (const RayVotes::Entry& e : ray.entries) {
      auto& cell = votes[&*e.cell];
      (e.matter ? cell.second : cell.first) += e.weight_q;
    }
  };
  for (std::uint32_t i = 0; i < snapshot.point_ids.size(); ++i) walk(i, snapshot.cloud.camera_index[i]);
  for (const Observation& o : snapshot.extra) walk(o.point, o.camera);
  return votes;
}

TEST(VoteMode, RayVotesEqualTheExactWalksOfTheLiveRaysAfterEachUpdate) {
  MapOptions options;
  options.visibility = Visibility::kRays;
  Parts parts(options);
  const MapUpdateResult first = LocateInsertVote(&parts, WallPoints({0.0, 0.0, 1.0}, 0.0));
  EXPECT_EQ(first.inserted, 28u);
  EXPECT_EQ(first.rays_traced, 28u);
  EXPECT_EQ(CellsDiffering(parts.state.dt, WalkedVotes(parts.state, parts.votes->ExportSnapshot())), 0);

  // The second frame's points fall between the first's: their insertion destroys cells the first rays
  // crossed, which are retraced in the new cells only; one more ray sees a first-frame point.
  const std::vector<Observation> extra = {{first.point_ids[3], 0}};
  const MapUpdateResult second = LocateInsertVote(&parts, WallPoints({0.8, 0.5, 1.2}, 0.5), extra);
  EXPECT_EQ(second.inserted, 28u);
  EXPECT_GT(second.rays_retraced, 0u);
  EXPECT_EQ(second.rays_traced, 29u);
  EXPECT_EQ(parts.votes->LiveRays(), 57u);
  EXPECT_EQ(CellsDiffering(parts.state.dt, WalkedVotes(parts.state, parts.votes->ExportSnapshot())), 0);
}

TEST(VoteMode, RaysRejectAnObservationOfAnUnknownPointAndHoldNothing) {
  MapOptions options;
  options.visibility = Visibility::kRays;
  Parts parts(options);
  LocateInsertVote(&parts, WallPoints({0.0, 0.0, 1.0}, 0.0));
  const std::int64_t frame = parts.state.frame;
  EXPECT_THROW(parts.votes->CheckInput(WallPoints({0.0, 0.0, 1.0}, 0.5), {{12345, 0}}),
               std::invalid_argument);
  EXPECT_EQ(parts.state.frame, frame);
  EXPECT_FALSE(parts.votes->HoldsPoints());
}

// ---- Depth maps ----

constexpr int kWidthPx = 64;
constexpr int kHeightPx = 48;
constexpr double kFocalPx = 40.0;
constexpr double kWallDepthM = 6.0;

// The camera at the origin looking along +z (world = camera frame) at a wall kWallDepthM away.
std::shared_ptr<const DepthView> WallView() {
  auto view = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 30.0);
  view->depth_m.setTo(float(kWallDepthM));
  return view;
}

// The wall's points at the pixels (u0 + 12i, v0 + 12j) for each u0 = v0 of `starts`: a point lands on the
// grid cells (map.merge_radius_px, 3 px) of no other when the starts differ by 6 px.
LabelledCloud WallPixels(const std::shared_ptr<const DepthView>& view, const std::vector<double>& starts) {
  LabelledCloud frame;
  frame.camera_centers_world = {Eigen::Vector3d::Zero()};
  frame.camera_views = {view};
  for (const double start : starts) {
    for (double u = start; u < kWidthPx; u += 12.0) {
      for (double v = start; v < kHeightPx; v += 12.0) {
        const double x = (u - view->intrinsics.cx_px) / kFocalPx, y = (v - view->intrinsics.cy_px) / kFocalPx;
        frame.positions_world.push_back(kWallDepthM * Eigen::Vector3d(x, y, 1.0));
        frame.camera_index.push_back(0);
      }
    }
  }
  return frame;
}

TEST(VoteMode, DepthVotesAreTheWindowsViewsVotesAndAViewSeenAgainMergesIntoItsVertices) {
  MapOptions options;
  options.merge_radius_px = 3.0;  // the grid WallPixels' points are laid out on
  Parts parts(options);
  const auto view = WallView();
  const VotingView voting(view);
  const DepthVoteGeometry geometry(options);
  const LabelledCloud frame = WallPixels(view, {3.5});

  // One view: every cell is new, voted by that view.
  const MapUpdateResult first = LocateInsertVote(&parts, frame);
  EXPECT_EQ(first.inserted, frame.size());
  CellVoteMap expected;
  for (auto c = parts.state.dt.finite_cells_begin(); c != parts.state.dt.finite_cells_end(); ++c) {
    const VoteIncrement v = VoteCell(Vertices(c), voting, geometry);
    expected[&*c] = {v.free_q, v.matter_q};
  }
  EXPECT_EQ(CellsDiffering(parts.state.dt, expected), 0);
  EXPECT_GT(first.cells_voted, 0u);

  // The same view again, with points at other pixels too: the old points merge into their vertices, the new
  // ones are inserted; the cells they create get the votes of both views of the window (those neither sees
  // keep the votes they inherited, not checked), the old cells the newest view's on top of theirs.
  const CellVoteMap before = VotesOf(parts.state.dt);
  const LabelledCloud again = WallPixels(view, {3.5, 9.5});
  const MapUpdateResult second = LocateInsertVote(&parts, again);
  EXPECT_EQ(second.merged, frame.size());
  EXPECT_EQ(second.inserted, again.size() - frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i) EXPECT_EQ(second.point_ids[i], first.point_ids[i]) << i;
  expected.clear();
  int created = 0;
  for (auto c = parts.state.dt.finite_cells_begin(); c != parts.state.dt.finite_cells_end(); ++c) {
    const VoteIncrement v = VoteCell(Vertices(c), voting, geometry);
    if (c->info().created == parts.state.update.created_mark) {
      if (v.free_q == 0 && v.matter_q == 0) continue;
      ++created;
      expected[&*c] = {2 * v.free_q, 2 * v.matter_q};
    } else {
      const auto& old = before.at(&*c);
      expected[&*c] = {old.first + v.free_q, old.second + v.matter_q};
    }
  }
  EXPECT_GT(created, 0);
  EXPECT_EQ(CellsDiffering(parts.state.dt, expected, /*unnamed_expect_none=*/false), 0);
}

TEST(VoteMode, DepthVotesNeedADepthViewPerCameraAndExportNoSnapshot) {
  MapOptions options;
  Parts parts(options);
  LabelledCloud frame = WallPixels(WallView(), {3.5});
  EXPECT_THROW(parts.votes->CheckInput(frame, {{0, 0}}), std::invalid_argument);
  frame.camera_views.clear();
  EXPECT_THROW(parts.votes->CheckInput(frame, {}), std::invalid_argument);
  EXPECT_THROW(parts.votes->ExportSnapshot(), std::logic_error);
  EXPECT_EQ(parts.votes->LiveRays(), 0u);
}

}  // namespace
}  // namespace semap::map_internal
