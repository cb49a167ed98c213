#include "engine/eval/depth_render.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semap {
namespace {

StereoCalibration SmallCamera() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 100.0;
  c.cx_px = 79.5;
  c.cy_px = 59.5;
  c.baseline_m = 0.5;
  c.width_px = 160;
  c.height_px = 120;
  return c;
}

// A square of half-size `h` in the plane through `centre` spanned by unit vectors `a`, `b`.
Mesh Quad(const Eigen::Vector3d& centre, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double h) {
  Mesh m;
  m.vertices = {centre - h * a - h * b, centre + h * a - h * b, centre + h * a + h * b,
                centre - h * a + h * b};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(RenderDepth, FrontoParallelPlaneHasConstantDepthEverywhere) {
  const auto cal = SmallCamera();
  const Mesh plane = Quad({0, 0, 10}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 100.0);
  const cv::Mat d = RenderDepth(plane, cal, Pose3d::Identity());
  for (int y = 0; y < d.rows; ++y) {
    for (int x = 0; x < d.cols; ++x) ASSERT_NEAR(d.at<float>(y, x), 10.0f, 1e-5) << x << "," << y;
  }
}

TEST(RenderDepth, TiltedPlaneMatchesRayPlaneIntersectionPerPixel) {
  const auto cal = SmallCamera();
  // Plane n·X = 8 with n tilted 40° about x (like the ground seen from a car) and 20° about y.
  const Eigen::Vector3d n = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ())
                                .normalized();
  const Eigen::Vector3d centre = 8.0 * n;
  const Eigen::Vector3d a = n.unitOrthogonal();
  const Eigen::Vector3d b = n.cross(a);
  const cv::Mat d = RenderDepth(Quad(centre, a, b, 200.0), cal, Pose3d::Identity());
  int checked = 0;
  for (int y = 0; y < d.rows; ++y) {
    for (int x = 0; x < d.cols; ++x) {
      const Eigen::Vector3d ray((x - cal.cx_px) / cal.fx_px, (y - cal.cy_px) / cal.fy_px, 1.0);
      const double denom = n.dot(ray);
      if (denom <= 1e-3) continue;
      const double z = 8.0 / denom;
      ASSERT_NEAR(d.at<float>(y, x), z, 1e-4 * z) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000);
}

TEST(RenderDepth, NearerSurfaceOccludesAndHolesStayEmpty) {
  const auto cal = SmallCamera();
  Mesh far = Quad({0, 0, 20}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 100.0);
  const Mesh near = Quad({0, 0, 5}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 1.0);  // ±20 px
  const auto offset = static_cast<std::uint32_t>(far.vertices.size());
  for (const auto& v : near.vertices) far.vertices.push_back(v);
  for (const auto& t : near.triangles) far.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const cv::Mat d = RenderDepth(far, cal, Pose3d::Identity());
  EXPECT_NEAR(d.at<float>(60, 80), 5.0f, 1e-5);   // centre: the small near quad
  EXPECT_NEAR(d.at<float>(10, 10), 20.0f, 1e-5);  // corner: the far plane
  // Only the small quad: pixels outside its ±20 px square are holes (0).
  const cv::Mat only_near = RenderDepth(near, cal, Pose3d::Identity());
  EXPECT_EQ(only_near.at<float>(10, 10), 0.0f);
  // u spans 79.5 ± 100·1/5 = [59.5, 99.5]: pixel centres 60..99 (40 columns); v spans [39.5, 79.5]: 40 rows.
  EXPECT_EQ(cv::countNonZero(only_near), 40 * 40);
}

TEST(RenderDepth, TrianglesCrossingTheCameraPlaneAreClipped) {
  const auto cal = SmallCamera();
  // Ground plane y = 1.5 (camera height 1.5 m, y down) from z = -50 to z = 50: half behind the camera.
  Mesh ground;
  ground.vertices = {{-50, 1.5, -50}, {50, 1.5, -50}, {50, 1.5, 50}, {-50, 1.5, 50}};
  ground.triangles = {{0, 1, 2}, {0, 2, 3}};
  const cv::Mat d = RenderDepth(ground, cal, Pose3d::Identity());
  // Below the horizon (v > cy) each pixel sees the ground at z = 1.5 fy / (v − cy) up to 50 m.
  for (int y = 62; y < d.rows; ++y) {
    const double z = 1.5 * cal.fy_px / (y - cal.cy_px);
    if (z > 50.0) continue;
    EXPECT_NEAR(d.at<float>(y, 80), z, 1e-4 * z) << "row " << y;
  }
  EXPECT_EQ(d.at<float>(10, 80), 0.0f);  // sky
}

TEST(RenderDepth, CameraPoseIsApplied) {
  const auto cal = SmallCamera();
  const Mesh plane = Quad({0, 0, 10}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 100.0);
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.translation() = Eigen::Vector3d(3, -2, 4);  // 6 m from the plane
  const cv::Mat d = RenderDepth(plane, cal, world_from_cam);
  EXPECT_NEAR(d.at<float>(60, 80), 6.0f, 1e-5);
}

TEST(RenderDepthAndTriangles, TellsTheNearestTriangleAndKeepsRenderDepthsDepth) {
  const auto cal = SmallCamera();
  // A far plane (triangles 0, 1) and a small near square in front of its centre (triangles 2, 3).
  Mesh m = Quad({0, 0, 20}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 100.0);
  const Mesh near = Quad({0, 0, 5}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 0.5);
  for (const auto& t : near.triangles) m.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});
  m.vertices.insert(m.vertices.end(), near.vertices.begin(), near.vertices.end());
  const DepthAndTriangles r = RenderDepthAndTriangles(m, cal, Pose3d::Identity());
  const cv::Mat d = RenderDepth(m, cal, Pose3d::Identity());
  ASSERT_EQ(r.triangle.type(), CV_32S);
  EXPECT_EQ(cv::norm(r.depth, d, cv::NORM_INF), 0.0);
  int near_pixels = 0;
  for (int y = 0; y < d.rows; ++y) {
    for (int x = 0; x < d.cols; ++x) {
      const int t = r.triangle.at<int>(y, x);
      ASSERT_GE(t, 0) << x << "," << y;
      // The near square covers |u - cx| <= 100 * 0.5 / 5 = 10 px (edges belong to both).
      if (d.at<float>(y, x) < 10.0f) {
        EXPECT_TRUE(t == 2 || t == 3) << x << "," << y;
        ++near_pixels;
      } else {
        EXPECT_TRUE(t == 0 || t == 1) << x << "," << y;
      }
    }
  }
  EXPECT_EQ(near_pixels, 20 * 20);
  // Nothing in view: −1 everywhere.
  Pose3d ahead = Pose3d::Identity();
  ahead.translation() = Eigen::Vector3d(0, 0, 10);
  const DepthAndTriangles behind = RenderDepthAndTriangles(near, cal, ahead);
  EXPECT_EQ(cv::countNonZero(behind.triangle != -1), 0);
}

}  // namespace
}  // namespace semap
