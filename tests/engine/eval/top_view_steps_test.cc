// The steps of RenderTopView (internal/top_view_steps.h) on tiny meshes seen from above, against references
// the test computes another way: pixel centres mapped back to the world and tested against each triangle by
// solving for their barycentric coordinates, the view's size from the fitting rule by hand, the shading from
// its formula.
#include "engine/eval/internal/top_view_steps.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace semap::eval_internal {
namespace {

TopViewOptions Plain(int size) {
  TopViewOptions o;
  o.max_width_px = o.max_height_px = size;
  o.margin_px = 10;
  o.legend = false;
  return o;
}

// A mesh of horizontal triangles (z = their height), each given by three (x, y) corners.
Mesh Horizontal(const std::vector<std::array<Eigen::Vector2d, 3>>& corners,
                const std::vector<double>& heights) {
  Mesh m;
  for (size_t t = 0; t < corners.size(); ++t) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (const auto& c : corners[t]) m.vertices.emplace_back(c.x(), c.y(), heights[t]);
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

// The world (x, y) a pixel centre of a view from above sees.
Eigen::Vector2d WorldAt(const TopView& v, int x, int y) {
  return {v.right_min + (x + 0.5 - v.margin_px) * v.metres_per_px,
          v.up_max - (y + 0.5 - v.margin_px) * v.metres_per_px};
}

// Whether `p` is inside the triangle (a, b, c), by its barycentric coordinates from a 2 × 2 solve.
bool Inside(const Eigen::Vector2d& p, const std::array<Eigen::Vector2d, 3>& t) {
  Eigen::Matrix2d m;
  m.col(0) = t[1] - t[0];
  m.col(1) = t[2] - t[0];
  const Eigen::Vector2d st = m.inverse() * (p - t[0]);
  return st.x() >= 0.0 && st.y() >= 0.0 && st.x() + st.y() <= 1.0;
}

struct Rendered {
  Projection proj;
  TopView view;
  ViewSize size;
  ZBuffer z;
};

Rendered Rasterise(const Mesh& mesh, const TopViewOptions& o) {
  Rendered r;
  r.proj = MakeProjection({0, 0, 1}, o);
  r.size = FitView(ProjectedExtent(mesh, r.proj, {}), r.proj, o, &r.view);
  r.z = EmptyRaster(r.size, &r.view);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    RasteriseTriangle(mesh, t, r.proj.into, r.size.height, &r.view, &r.z);
  return r;
}

TEST(TopViewSteps, FromAboveTheAxesAreXRightYUpAndDownTheViewingDirection) {
  const Projection p = MakeProjection({0, 0, 2}, Plain(100));
  EXPECT_NEAR((p.right - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p.image_up - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p.into + Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  // A quarter turn of azimuth: image right is +y.
  TopViewOptions turned = Plain(100);
  turned.azimuth_deg = 90.0;
  EXPECT_NEAR((MakeProjection({0, 0, 1}, turned).right - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
}

TEST(TopViewSteps, TheViewFitsTheExtentIntoTheImageWithinTheMargins) {
  const Mesh m = Horizontal({{{{-5.0, -2.0}, {5.0, -2.0}, {0.0, 3.0}}}}, {1.0});
  const Projection p = MakeProjection({0, 0, 1}, Plain(200));
  const ViewExtent e = ProjectedExtent(m, p, {{0.0, 8.0, 0.0}});  // the track widens the box upwards
  EXPECT_NEAR(e.a_min, -5.0, 1e-12);
  EXPECT_NEAR(e.a_max, 5.0, 1e-12);
  EXPECT_NEAR(e.b_min, -2.0, 1e-12);
  EXPECT_NEAR(e.b_max, 8.0, 1e-12);
  TopView v;
  // 10 m × 10 m into 180 × 180 px: 18 px/m, 200 × 200 px.
  const ViewSize s = FitView(e, p, Plain(200), &v);
  EXPECT_EQ(s.width, 200);
  EXPECT_EQ(s.height, 200);
  EXPECT_DOUBLE_EQ(v.metres_per_px, 1.0 / 18.0);
  // Without the track: 10 m × 5 m at 18 px/m, the height shrinks to the content (90 px + margins).
  TopView w;
  const ViewSize t = FitView(ProjectedExtent(m, p, {}), p, Plain(200), &w);
  EXPECT_EQ(t.width, 200);
  EXPECT_EQ(t.height, 110);
  EXPECT_EQ(t.rows, 110);
  // With the legend strip below: 30 rows more, and the mesh fitted above it.
  TopViewOptions legend = Plain(200);
  legend.legend = true;
  const ViewSize u = FitView(e, p, legend, &w);
  EXPECT_EQ(u.rows, u.height + 30);
  EXPECT_DOUBLE_EQ(w.metres_per_px, 10.0 / 150.0);
  // A mesh without triangles is the unit box.
  const ViewExtent none = ProjectedExtent(Mesh(), p, {{5.0, 5.0, 5.0}});
  EXPECT_EQ(none.a_min, 0.0);
  EXPECT_EQ(none.b_max, 1.0);
}

TEST(TopViewSteps, ATriangleCoversThePixelCentresInsideIt) {
  const std::array<Eigen::Vector2d, 3> t = {Eigen::Vector2d(-3.1, -1.7), {4.3, -0.9}, {0.7, 2.9}};
  const Mesh m = Horizontal({t}, {1.25});
  const Rendered r = Rasterise(m, Plain(64));
  int covered = 0;
  for (int y = 0; y < r.size.rows; ++y) {
    for (int x = 0; x < r.size.width; ++x) {
      const Eigen::Vector2d w = WorldAt(r.view, x, y);
      const bool inside = Inside(w, t);
      ASSERT_EQ(r.view.triangle.at<int>(y, x) == 0, inside) << "pixel " << x << ", " << y;
      if (!inside) {
        EXPECT_EQ(r.z.depth.at<double>(y, x), std::numeric_limits<double>::infinity());
        continue;
      }
      ++covered;
      const cv::Vec3d p = r.view.points.at<cv::Vec3d>(y, x);
      EXPECT_NEAR(p[0], w.x(), 1e-9);
      EXPECT_NEAR(p[1], w.y(), 1e-9);
      EXPECT_NEAR(p[2], 1.25, 1e-12);
      EXPECT_NEAR(r.z.depth.at<double>(y, x), -1.25, 1e-9);  // depth along the viewing direction, −z
    }
  }
  EXPECT_GT(covered, 200);
}

TEST(TopViewSteps, TheNearerTriangleWinsWhereTwoOverlap) {
  // A low triangle drawn first, a high one over half of it drawn second; and the other order.
  const std::array<Eigen::Vector2d, 3> low = {Eigen::Vector2d(-4.1, -3.3), {4.2, -3.1}, {0.1, 4.05}};
  const std::array<Eigen::Vector2d, 3> high = {Eigen::Vector2d(-0.3, -3.9), {4.4, -3.7}, {4.3, 3.9}};
  for (const bool high_first : {false, true}) {
    const Mesh m = high_first ? Horizontal({high, low}, {3.0, 1.0}) : Horizontal({low, high}, {1.0, 3.0});
    const int low_id = high_first ? 1 : 0, high_id = 1 - low_id;
    const Rendered r = Rasterise(m, Plain(80));
    int both = 0;
    for (int y = 0; y < r.size.rows; ++y) {
      for (int x = 0; x < r.size.width; ++x) {
        const Eigen::Vector2d w = WorldAt(r.view, x, y);
        const int want = Inside(w, high) ? high_id : Inside(w, low) ? low_id : -1;
        ASSERT_EQ(r.view.triangle.at<int>(y, x), want) << "pixel " << x << ", " << y;
        both += Inside(w, high) && Inside(w, low);
      }
    }
    EXPECT_GT(both, 100);
    const HeightRange h = CoveredHeights(r.view, {0, 0, 1});
    EXPECT_DOUBLE_EQ(h.low, 1.0);
    EXPECT_DOUBLE_EQ(h.high, 3.0);
  }
}

TEST(TopViewSteps, AnEdgeOnTriangleCoversNothing) {
  Mesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 1}, {1, 0, 3}};  // in the plane y = 0: a line seen from above
  m.triangles = {{0, 1, 2}};
  const Rendered r = Rasterise(m, Plain(50));
  EXPECT_EQ(cv::countNonZero(r.view.triangle >= 0), 0);
}

TEST(TopViewSteps, ShadingScalesTheBaseColourByTheLightOnTheNormal) {
  const Mesh m = Horizontal({{{{-2.0, -2.0}, {2.0, -1.5}, {0.5, 2.0}}}}, {0.0});
  const Rendered r = Rasterise(m, Plain(40));
  const cv::Mat image = ShadeImage(m, r.proj, r.view, r.z.base);
  // A horizontal triangle's normal is ±z; the light is −into + 0.5 right + 0.3 up = (0.5, 0.3, 1),
  // normalised.
  const double shade = 0.35 + 0.65 * 1.0 / std::sqrt(0.25 + 0.09 + 1.0);
  const int grey = static_cast<int>(std::lround(200.0 * shade));
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b c = image.at<cv::Vec3b>(y, x);
      const cv::Vec3b want =
          r.view.triangle.at<int>(y, x) < 0 ? cv::Vec3b(255, 255, 255) : cv::Vec3b(grey, grey, grey);
      ASSERT_EQ(c, want) << "pixel " << x << ", " << y;
    }
  }
}

TEST(TopViewSteps, HeightColoursRunFromBlueAtTheLowestToRedAtTheHighest) {
  const std::array<Eigen::Vector2d, 3> a = {Eigen::Vector2d(-4.0, -3.0), {-0.5, -3.0}, {-2.0, 3.0}};
  const std::array<Eigen::Vector2d, 3> b = {Eigen::Vector2d(0.5, -3.0), {4.0, -3.0}, {2.0, 3.0}};
  const Mesh m = Horizontal({a, b}, {1.0, 5.0});
  Rendered r = Rasterise(m, Plain(60));
  TopViewOptions o = Plain(60);
  o.colour = TopViewColour::kHeight;
  ColourByHeightOrError(r.view, o, {}, {0, 0, 1}, CoveredHeights(r.view, {0, 0, 1}), &r.z.base);
  int seen = 0;
  for (int y = 0; y < r.size.rows; ++y) {
    for (int x = 0; x < r.size.width; ++x) {
      const int t = r.view.triangle.at<int>(y, x);
      const cv::Vec3f c = r.z.base.at<cv::Vec3f>(y, x);
      if (t < 0) {
        EXPECT_EQ(c, cv::Vec3f(200, 200, 200));  // the background keeps the grey base
        continue;
      }
      ++seen;
      // The points' heights are barycentric means of equal heights: equal to a few ulps.
      const cv::Vec3f want = t == 0 ? cv::Vec3f(200, 60, 40) : cv::Vec3f(40, 40, 210);
      EXPECT_LT(cv::norm(c - want), 1e-3) << "pixel " << x << ", " << y;
    }
  }
  EXPECT_GT(seen, 100);
}

TEST(TopViewSteps, ErrorColoursFollowTheBinsOfTheDistance) {
  const Mesh m = Horizontal({{{{-2.0, -2.0}, {2.0, -2.0}, {0.0, 2.0}}}}, {0.0});
  Rendered r = Rasterise(m, Plain(40));
  TopViewOptions o = Plain(40);
  o.colour = TopViewColour::kError;
  // Distance = |x| m: bins ≤ 0.2 (green), ≤ 0.5 (yellow), ≤ 2 (orange).
  const auto distance = [](const Eigen::Vector3d& p) { return std::abs(p.x()); };
  ColourByHeightOrError(r.view, o, distance, {0, 0, 1}, CoveredHeights(r.view, {0, 0, 1}), &r.z.base);
  const cv::Vec3f green(60, 170, 60), yellow(40, 210, 230), orange(30, 140, 240);
  for (int y = 0; y < r.size.rows; ++y) {
    for (int x = 0; x < r.size.width; ++x) {
      if (r.view.triangle.at<int>(y, x) < 0) continue;
      const double d = std::abs(r.view.points.at<cv::Vec3d>(y, x)[0]);
      const cv::Vec3f want = d <= 0.2 ? green : d <= 0.5 ? yellow : orange;
      EXPECT_EQ(r.z.base.at<cv::Vec3f>(y, x), want) << "pixel " << x << ", " << y;
    }
  }
}

TEST(TopViewSteps, TheTrackIsDrawnThroughItsPixels) {
  const Mesh m = Horizontal({{{{-5.0, -5.0}, {5.0, -5.0}, {0.0, 5.0}}}}, {0.0});
  Rendered r = Rasterise(m, Plain(100));
  r.view.image = ShadeImage(m, r.proj, r.view, r.z.base);
  const Eigen::Vector3d from(-4.0, 0.0, 0.0), to(4.0, 0.0, 0.0);
  DrawTrack({from, to}, &r.view);
  const Eigen::Vector2d mid = r.view.ToPixel(0.5 * (from + to));
  EXPECT_EQ(r.view.image.at<cv::Vec3b>(static_cast<int>(std::lround(mid.y())),
                                       static_cast<int>(std::lround(mid.x()))),
            cv::Vec3b(140, 40, 20));
  // One point is no line.
  const cv::Mat before = r.view.image.clone();
  DrawTrack({from}, &r.view);
  EXPECT_EQ(cv::norm(before, r.view.image, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace semap::eval_internal
