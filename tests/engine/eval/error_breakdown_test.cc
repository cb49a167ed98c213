#include "engine/eval/error_breakdown.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "engine/core/check.h"
#include "engine/eval/depth_render.h"

namespace semap {
namespace {

StereoCalibration TinyCamera() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 40.0;
  c.cx_px = 19.5;
  c.cy_px = 14.5;
  c.baseline_m = 0.5;
  c.width_px = 40;
  c.height_px = 30;
  return c;
}

// A fronto-parallel wall at z = 12 m of two big triangles (labels 3, building) and, in front of its
// centre, a road-labelled (1) square of side 2 m at z = 4 m cut into small triangles (a 4 × 4 grid, 0.125 m²
// each).
Mesh HandMadeMesh() {
  Mesh m;
  const double big = 50.0;
  m.vertices = {{-big, -big, 12}, {big, -big, 12}, {big, big, 12}, {-big, big, 12}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.labels = {3, 3, 3, 3};
  constexpr int kGrid = 4;
  const double step = 2.0 / kGrid;
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  for (int j = 0; j <= kGrid; ++j) {
    for (int i = 0; i <= kGrid; ++i) {
      m.vertices.emplace_back(-1.0 + i * step, -1.0 + j * step, 4.0);
      m.labels.push_back(1);
    }
  }
  const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (kGrid + 1) + i); };
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

// The reference depth of pixel (x, y): errors of every size, some pixels out of range, a few far ones.
float ReferenceAt(int x, int y) {
  if ((x + y) % 7 == 0) return 0.0f;                     // no reference
  if (x == 0) return 0.5f;                               // too near: not a reference pixel
  if (y == 0) return 45.0f;                              // too far
  if (x == 39) return 38.0f;                             // far: mesh (12 m) 26 m in front
  return static_cast<float>(4.0 + 0.37 * x + 0.11 * y);  // 4.4 .. 22 m
}

struct Expected {
  std::int64_t reference = 0;
  std::vector<double> errors;
  double Rmse() const {
    double s = 0.0;
    for (double e : errors) s += e * e;
    return std::sqrt(s / errors.size());
  }
  double Median() const {
    std::vector<double> a;
    for (double e : errors) a.push_back(std::abs(e));
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    return a[a.size() / 2];
  }
  double ShareLarge(double bound) const {
    return std::count_if(errors.begin(), errors.end(), [&](double e) { return std::abs(e) > bound; }) /
           static_cast<double>(errors.size());
  }
  double Mean() const {
    double s = 0.0;
    for (double e : errors) s += e;
    return s / errors.size();
  }
};

void ExpectBin(const ErrorBin& bin, const Expected& expected, double large_m, bool has_reference = true) {
  SCOPED_TRACE(bin.name);
  EXPECT_EQ(bin.compared_pixels, static_cast<std::int64_t>(expected.errors.size()));
  if (has_reference) {
    EXPECT_EQ(bin.reference_pixels, expected.reference);
  }
  if (expected.errors.empty()) return;
  EXPECT_NEAR(bin.rmse_m, expected.Rmse(), 1e-9);
  EXPECT_NEAR(bin.mean_error_m, expected.Mean(), 1e-9);
  EXPECT_NEAR(bin.median_abs_m, expected.Median(), 0.0005 + 1e-9);  // half a histogram cell
  EXPECT_NEAR(bin.share_large, expected.ShareLarge(large_m), 1e-12);
}

TEST(ErrorBreakdown, HandMadeCaseEqualsASimpleReferenceAndBinsAddUp) {
  const auto cal = TinyCamera();
  const Mesh mesh = HandMadeMesh();
  const DepthAndTriangles rendered = RenderDepthAndTriangles(mesh, cal, Pose3d::Identity());
  cv::Mat reference(cal.height_px, cal.width_px, CV_32F);
  for (int y = 0; y < reference.rows; ++y) {
    for (int x = 0; x < reference.cols; ++x) reference.at<float>(y, x) = ReferenceAt(x, y);
  }
  // A hole: the mesh misses a column.
  cv::Mat mesh_depth = rendered.depth.clone();
  mesh_depth.col(5).setTo(0.0f);

  const std::vector<double> areas = TriangleAreas(mesh);
  ASSERT_EQ(areas.size(), 2u + 32u);
  EXPECT_NEAR(areas[0], 0.5 * 100.0 * 100.0, 1e-9);
  EXPECT_NEAR(areas[2], 0.125, 1e-12);
  const std::vector<int> triangle_labels = TriangleLabels(mesh);
  EXPECT_EQ(triangle_labels.front(), 3);
  EXPECT_EQ(triangle_labels.back(), 1);

  DepthAccuracyOptions accuracy;  // 1–40 m
  ErrorBreakdownOptions options;
  ErrorBreakdownAccumulator acc(accuracy, options);
  const cv::Mat classes = PixelClasses(cv::Mat(), rendered.triangle, triangle_labels);
  acc.Add(reference, mesh_depth, rendered.triangle, areas, classes);
  const ErrorBreakdown b = acc.Result(ClassMap::Cityscapes());

  // The reference, pixel by pixel.
  std::map<int, Expected> by_class;
  std::vector<Expected> by_distance(options.distance_edges_m.size()),
      by_area(options.triangle_area_edges_m2.size());
  Expected all;
  for (int y = 0; y < reference.rows; ++y) {
    for (int x = 0; x < reference.cols; ++x) {
      const double r = reference.at<float>(y, x);
      if (r < 1.0 || r > 40.0) continue;
      const int t = rendered.triangle.at<int>(y, x);
      const int label = t < 0 ? -1 : (t < 2 ? 3 : 1);
      const int d = r < 5 ? 0 : r < 10 ? 1 : r < 15 ? 2 : r < 20 ? 3 : r < 30 ? 4 : r < 40 ? 5 : 6;
      ++all.reference;
      ++by_class[label].reference;
      ++by_distance[d].reference;
      if (x == 5) continue;  // the hole
      const double e = static_cast<double>(mesh_depth.at<float>(y, x)) - r;
      all.errors.push_back(e);
      by_class[label].errors.push_back(e);
      by_distance[d].errors.push_back(e);
      by_area[t < 2 ? 5 : 2].errors.push_back(e);  // 5000 m² (>= 100) or 0.125 m² (0.1–1)
    }
  }
  ASSERT_GT(all.errors.size(), 500u);
  ASSERT_GT(all.ShareLarge(2.0), 0.1);

  // Class bins: building (the wall) and road (the near square); the hole column still has its triangle.
  ASSERT_EQ(b.by_class.size(), 2u);
  EXPECT_EQ(b.by_class[0].name, "Road");
  EXPECT_EQ(b.by_class[1].name, "Building");
  ExpectBin(b.by_class[0], by_class[1], 2.0);
  ExpectBin(b.by_class[1], by_class[3], 2.0);
  ASSERT_EQ(b.by_distance.size(), 7u);
  EXPECT_EQ(b.by_distance[1].name, "5-10 m");
  EXPECT_EQ(b.by_distance[6].name, ">= 40 m");
  EXPECT_TRUE(std::isinf(b.by_distance[6].high));
  for (std::size_t i = 0; i < b.by_distance.size(); ++i) ExpectBin(b.by_distance[i], by_distance[i], 2.0);
  ASSERT_EQ(b.by_triangle_area.size(), 6u);
  EXPECT_EQ(b.by_triangle_area[2].name, "0.1-1 m2");
  for (std::size_t i = 0; i < b.by_triangle_area.size(); ++i) {
    ExpectBin(b.by_triangle_area[i], by_area[i], 2.0, /*has_reference=*/false);
  }

  // Every breakdown adds up to the whole.
  for (const auto* bins : {&b.by_class, &b.by_distance, &b.by_triangle_area}) {
    std::int64_t compared = 0, large = 0;
    double sum_sq = 0.0;
    for (const ErrorBin& bin : *bins) {
      compared += bin.compared_pixels;
      large += bin.large_pixels;
      sum_sq += bin.rmse_m * bin.rmse_m * bin.compared_pixels;
    }
    EXPECT_EQ(compared, static_cast<std::int64_t>(all.errors.size()));
    EXPECT_NEAR(large, all.ShareLarge(2.0) * all.errors.size(), 1e-6);
    EXPECT_NEAR(std::sqrt(sum_sq / compared), all.Rmse(), 1e-9);
  }
  std::int64_t total_reference = 0;
  for (const ErrorBin& bin : b.by_distance) total_reference += bin.reference_pixels;
  EXPECT_EQ(total_reference, all.reference);
  // The same pixels and totals as the accuracy measure.
  DepthAccuracyAccumulator total(accuracy);
  total.Add(reference, mesh_depth);
  EXPECT_EQ(total.Result().reference_pixels, all.reference);
  EXPECT_EQ(total.Result().compared_pixels, static_cast<std::int64_t>(all.errors.size()));
  EXPECT_NEAR(total.Result().rmse_m, all.Rmse(), 1e-9);
}

TEST(ErrorBreakdown, FrameLabelsWinOverTheMeshAndUnknownPixelsAreNoClass) {
  cv::Mat triangle = (cv::Mat_<int>(1, 3) << 0, 1, -1);
  const std::vector<int> triangle_labels = {7, 9};
  const cv::Mat from_mesh = PixelClasses(cv::Mat(), triangle, triangle_labels);
  EXPECT_EQ(from_mesh.at<int>(0, 0), 7);
  EXPECT_EQ(from_mesh.at<int>(0, 1), 9);
  EXPECT_EQ(from_mesh.at<int>(0, 2), -1);
  const cv::Mat frame_labels = (cv::Mat_<std::uint8_t>(1, 3) << 11, 12, 13);
  const cv::Mat from_frame = PixelClasses(frame_labels, triangle, triangle_labels);
  EXPECT_EQ(from_frame.at<int>(0, 2), 13);
  EXPECT_EQ(cv::countNonZero(PixelClasses(cv::Mat(), triangle, {}) != -1), 0);

  // Without classes every pixel is "no class"; an id the class map lacks is named by number.
  cv::Mat ref = (cv::Mat_<float>(1, 3) << 10, 10, 10);
  cv::Mat mesh = (cv::Mat_<float>(1, 3) << 10.5f, 13, 0);
  ErrorBreakdownAccumulator acc{DepthAccuracyOptions()};
  acc.Add(ref, mesh, triangle, {1.0, 2.0}, cv::Mat());
  cv::Mat odd = (cv::Mat_<int>(1, 3) << 200, 200, 200);
  acc.Add(ref, mesh, triangle, {1.0, 2.0}, odd);
  const ErrorBreakdown b = acc.Result(ClassMap::Cityscapes());
  ASSERT_EQ(b.by_class.size(), 2u);
  EXPECT_EQ(b.by_class[0].name, "label 200");
  EXPECT_EQ(b.by_class[1].name, "no class");
  EXPECT_EQ(b.by_class[1].reference_pixels, 3);
  EXPECT_EQ(b.by_class[1].compared_pixels, 2);
  EXPECT_DOUBLE_EQ(b.by_class[1].completeness, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(b.by_class[1].share_large, 0.5);
  EXPECT_NEAR(b.by_class[1].median_abs_m, 3.0, 0.0005 + 1e-9);  // the (n / 2)-th of {0.5, 3}
  EXPECT_NEAR(b.by_class[1].mean_error_m, 1.75, 1e-9);
}

TEST(ErrorBreakdown, MovablePixelsLeaveTheStaticReference) {
  const ClassMap cityscapes = ClassMap::Cityscapes();
  const std::vector<int> movable = MovableClassIds(cityscapes);
  const int car = cityscapes.FindByName("car"), road = cityscapes.FindByName("road");
  const int person = cityscapes.FindByName("person"), bicycle = cityscapes.FindByName("bicycle");
  ASSERT_GE(car, 0);
  ASSERT_GE(road, 0);
  EXPECT_EQ(movable.size(), 8u);  // person, rider, car, truck, bus, train, motorcycle, bicycle
  for (const int id : {car, person, bicycle})
    EXPECT_NE(std::find(movable.begin(), movable.end(), id), movable.end());
  EXPECT_EQ(std::find(movable.begin(), movable.end(), road), movable.end());
  // A 2×3 reference: the car's pixels go, the road's and the unlabelled one stay, depths untouched.
  const cv::Mat reference = (cv::Mat_<float>(2, 3) << 5.0f, 6.0f, 0.0f, 7.0f, 8.0f, 9.0f);
  const cv::Mat labels = (cv::Mat_<std::uint8_t>(2, 3) << road, car, car, 0, car, road);
  const cv::Mat out = WithoutMovable(reference, labels, movable);
  const cv::Mat expected = (cv::Mat_<float>(2, 3) << 5.0f, 0.0f, 0.0f, 7.0f, 0.0f, 9.0f);
  EXPECT_EQ(cv::countNonZero(out != expected), 0);
  EXPECT_EQ(reference.at<float>(0, 1), 6.0f);  // the input is not changed
  // PixelClasses' classes (CV_32S, −1 = none) give the same.
  const cv::Mat classes = (cv::Mat_<int>(2, 3) << road, car, car, -1, car, road);
  EXPECT_EQ(cv::countNonZero(WithoutMovable(reference, classes, movable) != expected), 0);
}

TEST(ErrorBreakdown, BadOptionsAreNamed) {
  ErrorBreakdownOptions o;
  o.distance_edges_m = {0.0, 10.0, 5.0};
  EXPECT_THROW(o.Check(), InvalidOption);
  o = ErrorBreakdownOptions();
  o.triangle_area_edges_m2.clear();
  EXPECT_THROW(o.Check(), InvalidOption);
  o = ErrorBreakdownOptions();
  o.large_error_m = 0.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = ErrorBreakdownOptions();
  o.median_resolution_m = 1e-9;
  EXPECT_THROW(o.Check(), InvalidOption);
}

}  // namespace
}  // namespace semap
