// The projection grid against what a point's pixel says: the cell it lands in, the nearest point a cell
// keeps, and the match among the 3×3 cells around, closest in depth within the tolerance.
#include "engine/map/internal/projection_grid.h"

#include <gtest/gtest.h>

#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

constexpr double kFocalPx = 30.0;

// The world point (world = camera frame) at pixel (u, v), depth z, of a 60 × 30 px view.
Eigen::Vector3d AtPixel(double u, double v, double z) {
  return z * Eigen::Vector3d((u - 30.0) / kFocalPx, (v - 15.0) / kFocalPx, 1.0);
}

TEST(ProjectionGrid, PointsLandInTheCellOfTheirPixelAndMatchTheNearestDepthAround) {
  const VotingView view(test::PinholeDepthView(60, 30, kFocalPx, 50.0));
  ProjectionGrid grid(view, /*merge_radius_px=*/3.0);
  int gu = -1, gv = -1;
  double depth = 0.0;
  ASSERT_TRUE(grid.Locate(AtPixel(10.5, 4.5, 5.0), &gu, &gv, &depth));
  EXPECT_EQ(gu, 3);
  EXPECT_EQ(gv, 1);
  EXPECT_NEAR(depth, 5.0, 1e-12);
  EXPECT_FALSE(grid.Locate(AtPixel(10.5, 4.5, -5.0), &gu, &gv, &depth));  // behind the camera
  EXPECT_FALSE(grid.Locate(AtPixel(61.0, 4.5, 5.0), &gu, &gv, &depth));   // beyond the image

  grid.Offer(3, 1, 5.0, 1);
  grid.Offer(4, 1, 7.0, 2);
  EXPECT_EQ(grid.Match(3, 1, 6.9, 0.5), 2u);  // the closest depth of the 3×3 cells around
  EXPECT_EQ(grid.Match(3, 1, 5.2, 0.5), 1u);
  EXPECT_EQ(grid.Match(3, 1, 6.0, 0.5), kNoId);  // neither within the tolerance
  EXPECT_EQ(grid.Match(6, 1, 7.0, 1.0), kNoId);  // two cells away
  grid.Offer(3, 1, 4.0, 3);                      // nearer: the cell keeps it, and only it
  EXPECT_EQ(grid.Match(3, 1, 4.0, 0.1), 3u);
  EXPECT_EQ(grid.Match(3, 1, 5.0, 0.1), kNoId);
  grid.Offer(3, 1, 9.0, 4);  // farther: hidden behind what the cell holds
  EXPECT_EQ(grid.Match(3, 1, 9.0, 0.1), kNoId);
}

TEST(ProjectionGrid, CellsSpanTheMergeRadiusInFullResolutionPixels) {
  // A view downsampled by 2 (each pixel 4 rays): a 3 px merge radius is 1.5 of its pixels.
  auto half = test::PinholeDepthView(60, 30, kFocalPx, 50.0);
  half->rays_per_pixel = 4.0;
  const VotingView view(half);
  ProjectionGrid grid(view, 3.0);
  int gu = -1, gv = -1;
  double depth = 0.0;
  ASSERT_TRUE(grid.Locate(AtPixel(11.0, 5.0, 5.0), &gu, &gv, &depth));
  EXPECT_EQ(gu, 7);  // 11 / 1.5
  EXPECT_EQ(gv, 3);  // 5 / 1.5
}

}  // namespace
}  // namespace semap::map_internal
