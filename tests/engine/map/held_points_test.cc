// Held far points: matched only by later frames, confirmed or dropped after the window, all taken at the end.
#include "engine/map/internal/held_points.h"

#include <gtest/gtest.h>

#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

constexpr double kFocalPx = 30.0;

Eigen::Vector3d AtPixel(double u, double v, double z) {
  return z * Eigen::Vector3d((u - 30.0) / kFocalPx, (v - 15.0) / kFocalPx, 1.0);
}

class HeldPointsTest : public ::testing::Test {
 protected:
  HeldPointsTest() : view_(test::PinholeDepthView(60, 30, kFocalPx, 50.0)), grid_(view_, 3.0) {
    options_.confirm_window_frames = 2;
    options_.merge_radius_px = 3.0;
    options_.merge_depth_fraction = 0.03;
  }
  // The grid cell of `p` in the view.
  std::pair<int, int> Cell(const Eigen::Vector3d& p) {
    int gu = 0, gv = 0;
    double depth = 0.0;
    EXPECT_TRUE(grid_.Locate(p, &gu, &gv, &depth));
    return {gu, gv};
  }
  MapOptions options_;
  VotingView view_;
  ProjectionGrid grid_;
};

TEST_F(HeldPointsTest, ALaterFrameConfirmsWhatAnEarlierOneHeld) {
  HeldPoints held(options_);
  const Eigen::Vector3d p = AtPixel(20.5, 10.5, 25.0);
  const auto [gu, gv] = Cell(p);
  held.StartFrame(0);
  held.AddView(view_);
  held.Hold({p, {}, 25.0, 0});
  EXPECT_EQ(held.Match(0, gu, gv, 25.0), kNoId);  // a frame does not confirm its own points
  held.DropConfirmed();
  ASSERT_EQ(held.size(), 1u);

  const Eigen::Vector3d q = AtPixel(40.5, 10.5, 30.0);
  held.StartFrame(1);
  held.AddView(view_);
  EXPECT_EQ(held.Match(0, gu, gv, 25.5), 0u);     // within 3 % of its depth
  EXPECT_EQ(held.Match(0, gu, gv, 26.0), kNoId);  // beyond
  EXPECT_EQ(held.Match(0, gu + 2, gv, 25.0), kNoId);
  EXPECT_EQ(held.ConfirmedAs(0), kNoId);
  held.Confirm(0, 42);
  EXPECT_EQ(held.ConfirmedAs(0), 42u);
  held.Hold({q, {}, 30.0, 1});
  held.DropConfirmed();  // p leaves, confirmed; q waits
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].position, q);
}

TEST_F(HeldPointsTest, APointNotConfirmedWithinTheWindowIsDroppedAndTheRestTakenAtTheEnd) {
  HeldPoints held(options_);
  held.StartFrame(0);
  held.AddView(view_);
  held.Hold({AtPixel(20.5, 10.5, 25.0), {}, 25.0, 0});
  held.DropConfirmed();
  held.StartFrame(2);  // two frames later: still within the window
  held.Hold({AtPixel(40.5, 10.5, 30.0), {}, 30.0, 2});
  held.DropConfirmed();
  EXPECT_EQ(held.size(), 2u);
  held.StartFrame(3);  // the first is three frames old
  held.DropConfirmed();
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].frame, 2);
  const std::vector<HeldPoints::Held> all = held.TakeAll();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].depth_m, 30.0);
  EXPECT_TRUE(held.empty());
}

}  // namespace
}  // namespace semap::map_internal
