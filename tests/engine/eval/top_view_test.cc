#include "engine/eval/top_view.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

// Appends the quad a, b, c, d (two triangles) to `m`.
void AddQuad(Mesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
             const Eigen::Vector3d& d) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {a, b, c, d});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

int Covered(const TopView& v) { return cv::countNonZero(v.triangle >= 0); }

// Pixels of the image that differ from the white background (the legend strip is below the mesh's rows).
int NonWhite(const cv::Mat& image, int rows) {
  int n = 0;
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < image.cols; ++x) n += image.at<cv::Vec3b>(y, x) != cv::Vec3b(255, 255, 255) ? 1 : 0;
  }
  return n;
}

TopViewOptions NoLegend(int size) {
  TopViewOptions o;
  o.max_width_px = o.max_height_px = size;
  o.margin_px = 10;
  o.legend = false;
  return o;
}

TEST(TopView, ADiamondSeenFromAboveCoversHalfItsBox) {
  // A horizontal square turned by 45° (|x| + |y| <= 5, z = 2): its box is 10 m × 10 m, fitted into 180 px.
  Mesh m;
  AddQuad(m, {5, 0, 2}, {0, 5, 2}, {-5, 0, 2}, {0, -5, 2});
  const TopView v = RenderTopView(m, {0, 0, 1}, NoLegend(200));
  ASSERT_EQ(v.image.size(), cv::Size(200, 200));
  EXPECT_NEAR(v.metres_per_px, 10.0 / 180.0, 1e-12);
  const double expected = 0.5 * 180.0 * 180.0;  // half the box; the boundary is ~4 × 127 px long
  EXPECT_NEAR(Covered(v), expected, 4 * 127 * 0.5);
  EXPECT_EQ(NonWhite(v.image, v.image.rows), Covered(v));
  // The world point seen at the centre is the square's centre, at its height.
  const cv::Vec3d c = v.points.at<cv::Vec3d>(100, 100);
  EXPECT_NEAR(c[0], 0.0, 0.1);
  EXPECT_NEAR(c[1], 0.0, 0.1);
  EXPECT_DOUBLE_EQ(c[2], 2.0);
  // Corners of the box are background.
  EXPECT_EQ(v.triangle.at<int>(15, 15), -1);
}

TEST(TopView, OrientationIsNotMirroredAndFollowsTheUpAxis) {
  // A z-up world (KITTI raw): x to the right, y up the image. The small square at (+x, +y) is top right.
  Mesh m;
  AddQuad(m, {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0});
  AddQuad(m, {8, 8, 1}, {10, 8, 1}, {10, 10, 1}, {8, 10, 1});
  const TopView z_up = RenderTopView(m, {0, 0, 1}, NoLegend(200));
  EXPECT_EQ(z_up.triangle.at<int>(15, 185), 2);  // top right: the raised square (triangles 2, 3)
  EXPECT_EQ(z_up.triangle.at<int>(185, 15), 0);  // bottom left: the ground
  // Seen from below (up = −z) the raised square is hidden under the ground.
  const TopView from_below = RenderTopView(m, {0, 0, -1}, NoLegend(200));
  EXPECT_EQ(Covered(from_below), Covered(z_up));
  EXPECT_LT(from_below.triangle.at<int>(15, 185), 2);
  EXPECT_LT(from_below.triangle.at<int>(185, 15), 2);

  // The same scene in a y-down camera frame (KITTI odometry: x right, z forward), p' = (x, −z, y), seen along
  // up = −y: image right is x and image up is z, the same picture pixel for pixel.
  Mesh camera = m;
  for (auto& p : camera.vertices) p = Eigen::Vector3d(p.x(), -p.z(), p.y());
  const TopView y_down = RenderTopView(camera, {0, -1, 0}, NoLegend(200));
  EXPECT_EQ(cv::countNonZero(y_down.triangle != z_up.triangle), 0);
}

TEST(TopView, AWallIsAnEdgeFromAboveAndAFaceFromTheSide) {
  Mesh m;
  AddQuad(m, {0, 0, 0}, {10, 0, 0}, {10, 0, 5}, {0, 0, 5});    // vertical, in the plane y = 0
  AddQuad(m, {0, 1, 0}, {10, 1, 0}, {10, 11, 0}, {0, 11, 0});  // ground behind it
  const TopView top = RenderTopView(m, {0, 0, 1}, NoLegend(200));
  EXPECT_EQ(cv::countNonZero(top.triangle == 0) + cv::countNonZero(top.triangle == 1), 0);  // no wall pixel
  EXPECT_GT(Covered(top), 1000);
  TopViewOptions oblique = NoLegend(200);
  oblique.elevation_deg = 30.0;  // from the −y side, 30° above the horizon: the wall faces the viewer
  const TopView side = RenderTopView(m, {0, 0, 1}, oblique);
  EXPECT_GT(cv::countNonZero(side.triangle == 0) + cv::countNonZero(side.triangle == 1), 1000);
}

TEST(TopView, ColoursByHeightAndByError) {
  Mesh m;
  AddQuad(m, {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0});        // low, on the truth
  AddQuad(m, {20, 0, 10}, {30, 0, 10}, {30, 10, 10}, {20, 10, 10});  // high, 10 m off
  TopViewOptions o = NoLegend(400);
  o.colour = TopViewColour::kHeight;
  const TopView h = RenderTopView(m, {0, 0, 1}, o);
  const cv::Vec3b low = h.image.at<cv::Vec3b>(100, 70), high = h.image.at<cv::Vec3b>(100, 330);
  EXPECT_GT(low[0], low[2]);    // blue over red
  EXPECT_GT(high[2], high[0]);  // red over blue

  o.colour = TopViewColour::kError;
  const TopView e = RenderTopView(m, {0, 0, 1}, o, [](const Eigen::Vector3d& p) { return std::abs(p.z()); });
  const cv::Vec3b right = e.image.at<cv::Vec3b>(100, 70), wrong = e.image.at<cv::Vec3b>(100, 330);
  EXPECT_GT(right[1], right[2]);  // green
  EXPECT_GT(wrong[2], wrong[1]);  // red
  EXPECT_GT(wrong[2], wrong[0]);
}

TEST(TopView, TheTrackIsDrawnAndKeptInView) {
  Mesh m;
  AddQuad(m, {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0});
  // A track from (−10, 5) to (5, 5): the view widens to x = −10 and the line crosses the empty part.
  const TopView v = RenderTopView(m, {0, 0, 1}, NoLegend(200), {}, {{-10, 5, 1}, {5, 5, 1}});
  EXPECT_NEAR(v.metres_per_px, 20.0 / 180.0, 1e-12);
  const Eigen::Vector2d start = v.ToPixel({-10, 5, 1});
  EXPECT_NEAR(start.x(), 10.0, 1e-9);
  const Eigen::Vector2d empty = v.ToPixel({-5, 5, 1});  // on the track, off the mesh
  const cv::Vec3b c = v.image.at<cv::Vec3b>(static_cast<int>(empty.y()), static_cast<int>(empty.x()));
  EXPECT_NE(c, cv::Vec3b(255, 255, 255));
  EXPECT_EQ(v.triangle.at<int>(static_cast<int>(empty.y()), static_cast<int>(empty.x())), -1);
  EXPECT_GT(c[0], c[2]);  // dark blue
}

TEST(TopView, EmptyMeshLegendAndBadOptions) {
  TopViewOptions o;
  const TopView empty = RenderTopView(Mesh(), {0, 0, 1}, o);
  EXPECT_EQ(Covered(empty), 0);
  EXPECT_FALSE(empty.image.empty());
  // The legend strip lies below the mesh: the mesh keeps its pixels.
  Mesh m;
  AddQuad(m, {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0});
  o.max_width_px = o.max_height_px = 300;
  o.colour = TopViewColour::kError;
  const TopView with_legend = RenderTopView(m, {0, 0, 1}, o, [](const Eigen::Vector3d&) { return 0.0; });
  EXPECT_EQ(with_legend.image.rows, 300);
  EXPECT_EQ(Covered(with_legend), (300 - 24 - 30) * (300 - 24 - 30));
  EXPECT_GT(NonWhite(with_legend.image, with_legend.image.rows), Covered(with_legend));  // + the legend

  EXPECT_THROW(RenderTopView(m, {0, 0, 0}, TopViewOptions()), InvalidOption);
  TopViewOptions bad;
  bad.elevation_deg = 0.0;
  EXPECT_THROW(RenderTopView(m, {0, 0, 1}, bad), InvalidOption);
  bad = TopViewOptions();
  bad.error_bins_m = {0.5, 0.2, 2.0};
  EXPECT_THROW(bad.Check(), InvalidOption);
}

}  // namespace
}  // namespace semap
