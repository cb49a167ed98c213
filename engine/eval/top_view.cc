#include "engine/eval/top_view.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "engine/core/check.h"
#include "engine/core/parallel.h"
#include "engine/eval/internal/top_view_steps.h"

namespace semap {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLegendHeightPx = 30;
const cv::Vec3b kBackground(255, 255, 255);
// kError bin colours (BGR): green, yellow, orange, red.
const cv::Vec3f kErrorColours[4] = {{60, 170, 60}, {40, 210, 230}, {30, 140, 240}, {40, 40, 215}};

// Blue → cyan → green → yellow → red for t in [0, 1] (BGR).
cv::Vec3f HeightColour(double t) {
  static const cv::Vec3f stops[5] = {
      {200, 60, 40}, {210, 200, 40}, {60, 190, 60}, {40, 210, 230}, {40, 40, 210}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  return stops[i] * static_cast<float>(1.0 - f) + stops[i + 1] * static_cast<float>(f);
}

int ErrorBin(double d, const std::array<double, 3>& bins) {
  for (int i = 0; i < 3; ++i) {
    if (d <= bins[i]) return i;
  }
  return 3;
}

std::string Metres(double m) {
  char text[32];
  std::snprintf(text, sizeof(text), m >= 1.0 ? "%.0f m" : "%.1f m", m);
  return text;
}

void DrawLegend(const TopViewOptions& o, double metres_per_px, double low, double high, cv::Mat& image) {
  const int y = image.rows - kLegendHeightPx / 2;
  const cv::Scalar ink(40, 40, 40);
  // Scale bar: 1, 2 or 5 × 10^k metres, about a fifth of the width.
  const double target = 0.2 * image.cols * metres_per_px;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double length = decade;
  for (double f : {5.0, 2.0}) {
    if (f * decade <= target) {
      length = f * decade;
      break;
    }
  }
  const int bar_px = static_cast<int>(std::lround(length / metres_per_px));
  int x = o.margin_px;
  cv::line(image, {x, y}, {x + bar_px, y}, ink, 2);
  cv::line(image, {x, y - 4}, {x, y + 4}, ink, 1);
  cv::line(image, {x + bar_px, y - 4}, {x + bar_px, y + 4}, ink, 1);
  cv::putText(image, Metres(length), {x + bar_px + 6, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
              cv::LINE_AA);
  x += bar_px + 70;
  if (o.colour == TopViewColour::kError) {
    const std::string labels[4] = {"<= " + Metres(o.error_bins_m[0]), "<= " + Metres(o.error_bins_m[1]),
                                   "<= " + Metres(o.error_bins_m[2]), "> " + Metres(o.error_bins_m[2])};
    for (int i = 0; i < 4; ++i) {
      cv::rectangle(image, cv::Rect(x, y - 6, 12, 12), cv::Scalar(kErrorColours[i]), cv::FILLED);
      cv::putText(image, labels[i], {x + 16, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
      x += 100;
    }
    cv::putText(image, "distance to the true surface", {x, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
                cv::LINE_AA);
  } else if (o.colour == TopViewColour::kHeight) {
    for (int i = 0; i < 100; ++i) {
      cv::line(image, {x + i, y - 6}, {x + i, y + 6}, cv::Scalar(HeightColour(i / 99.0)), 1);
    }
    char text[64];
    std::snprintf(text, sizeof(text), "height %.1f .. %.1f m", low, high);
    cv::putText(image, text, {x + 106, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  }
}

}  // namespace

const char* TopViewColourName(TopViewColour colour) {
  switch (colour) {
    case TopViewColour::kMesh:
      return "mesh";
    case TopViewColour::kHeight:
      return "height";
    case TopViewColour::kError:
      return "error";
  }
  return "?";
}

void TopViewOptions::Check() const {
  SEMAP_CHECK_OPTION(max_width_px >= 16 && max_width_px <= 16384, "max_width_px", max_width_px,
                     "must be in [16, 16384]");
  SEMAP_CHECK_OPTION(max_height_px >= 16 && max_height_px <= 16384, "max_height_px", max_height_px,
                     "must be in [16, 16384]");
  SEMAP_CHECK_OPTION(margin_px >= 0 && 2 * margin_px + 8 <= max_width_px &&
                         2 * margin_px + (legend ? kLegendHeightPx : 0) + 8 <= max_height_px,
                     "margin_px", margin_px, "must be >= 0 and leave at least 8 px for the mesh");
  SEMAP_CHECK_OPTION(elevation_deg > 0.0 && elevation_deg <= 90.0, "elevation_deg", elevation_deg,
                     "must be in (0, 90]");
  SEMAP_CHECK_OPTION(std::isfinite(azimuth_deg), "azimuth_deg", azimuth_deg, "must be finite");
  SEMAP_CHECK_OPTION(
      error_bins_m[0] > 0.0 && error_bins_m[1] > error_bins_m[0] && error_bins_m[2] > error_bins_m[1],
      "error_bins_m", error_bins_m[0], "must be increasing and > 0");
}

Eigen::Vector2d TopView::ToPixel(const Eigen::Vector3d& p) const {
  return {margin_px + (right.dot(p) - right_min) / metres_per_px,
          margin_px + (up_max - image_up.dot(p)) / metres_per_px};
}

namespace eval_internal {

Projection MakeProjection(const Eigen::Vector3d& up_in, const TopViewOptions& o) {
  const Eigen::Vector3d up = up_in.normalized();
  int axis = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(up[i]) < std::abs(up[axis]) - 1e-9) axis = i;
  }
  Eigen::Vector3d h = Eigen::Vector3d::Unit(axis);
  h = (h - up * up.dot(h)).normalized();
  const double az = o.azimuth_deg * kPi / 180.0;
  const Eigen::Vector3d e1 = std::cos(az) * h + std::sin(az) * up.cross(h);
  const Eigen::Vector3d e2 = up.cross(e1);
  const double el = o.elevation_deg * kPi / 180.0;
  Projection p;
  p.right = e1;
  p.into = (std::cos(el) * e2 - std::sin(el) * up).normalized();
  p.image_up = p.right.cross(p.into);
  return p;
}

ViewExtent ProjectedExtent(const Mesh& mesh, const Projection& proj,
                           const std::vector<Eigen::Vector3d>& track) {
  if (mesh.triangles.empty()) return ViewExtent{};
  ViewExtent e;
  e.a_min = e.b_min = std::numeric_limits<double>::infinity();
  e.a_max = e.b_max = -std::numeric_limits<double>::infinity();
  const auto extend = [&e, &proj](const Eigen::Vector3d& p) {
    const double a = proj.right.dot(p), b = proj.image_up.dot(p);
    e.a_min = std::min(e.a_min, a), e.a_max = std::max(e.a_max, a), e.b_min = std::min(e.b_min, b),
    e.b_max = std::max(e.b_max, b);
  };
  for (const auto& t : mesh.triangles) {
    for (std::uint32_t v : t) extend(mesh.vertices[v]);
  }
  for (const Eigen::Vector3d& c : track) extend(c);
  return e;
}

ViewSize FitView(const ViewExtent& e, const Projection& proj, const TopViewOptions& options, TopView* view) {
  const int m = options.margin_px;
  const int legend_px = options.legend ? kLegendHeightPx : 0;
  const double span_a = std::max(e.a_max - e.a_min, 1e-6), span_b = std::max(e.b_max - e.b_min, 1e-6);
  const double px_per_m =
      std::min((options.max_width_px - 2 * m) / span_a, (options.max_height_px - 2 * m - legend_px) / span_b);
  ViewSize size;
  size.width = std::min(options.max_width_px, static_cast<int>(std::ceil(span_a * px_per_m)) + 2 * m);
  size.height =
      std::min(options.max_height_px - legend_px, static_cast<int>(std::ceil(span_b * px_per_m)) + 2 * m);
  size.rows = size.height + legend_px;
  view->right = proj.right;
  view->image_up = proj.image_up;
  view->margin_px = m;
  view->metres_per_px = 1.0 / px_per_m;
  view->right_min = e.a_min;
  view->up_max = e.b_max;
  return size;
}

ZBuffer EmptyRaster(const ViewSize& size, TopView* view) {
  ZBuffer z;
  z.depth = cv::Mat(size.rows, size.width, CV_64FC1, cv::Scalar(std::numeric_limits<double>::infinity()));
  view->triangle = cv::Mat(size.rows, size.width, CV_32SC1, cv::Scalar(-1));
  view->points = cv::Mat(size.rows, size.width, CV_64FC3, cv::Scalar(0, 0, 0));
  z.base = cv::Mat(size.rows, size.width, CV_32FC3, cv::Scalar(200, 200, 200));
  return z;
}

void RasteriseTriangle(const Mesh& mesh, std::size_t ti, const Eigen::Vector3d& into, int height,
                       TopView* view, ZBuffer* z) {
  const auto& t = mesh.triangles[ti];
  Eigen::Vector2d s[3];
  double zv[3];
  for (int k = 0; k < 3; ++k) {
    s[k] = view->ToPixel(mesh.vertices[t[k]]);
    zv[k] = into.dot(mesh.vertices[t[k]]);
  }
  const double area = (s[1] - s[0]).x() * (s[2] - s[0]).y() - (s[1] - s[0]).y() * (s[2] - s[0]).x();
  if (std::abs(area) < 1e-12) return;  // edge-on: covers no pixel centre
  const int width = view->triangle.cols;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}) - 0.5)));
  const int x1 =
      std::min(width - 1, static_cast<int>(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}) - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}) - 0.5)));
  const int y1 =
      std::min(height - 1, static_cast<int>(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}) - 0.5)));
  const bool vertex_colours = !mesh.colors_rgb.empty();
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d c(x + 0.5, y + 0.5);
      double w[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& p = s[(k + 1) % 3];
        const Eigen::Vector2d& q = s[(k + 2) % 3];
        w[k] = ((q - p).x() * (c - p).y() - (q - p).y() * (c - p).x()) / area;
      }
      if (w[0] < -1e-9 || w[1] < -1e-9 || w[2] < -1e-9) continue;  // centres on a shared edge: both
      const double zc = w[0] * zv[0] + w[1] * zv[1] + w[2] * zv[2];
      double& d = z->depth.at<double>(y, x);
      if (zc >= d) continue;
      d = zc;
      view->triangle.at<int>(y, x) = static_cast<int>(ti);
      const Eigen::Vector3d p =
          w[0] * mesh.vertices[t[0]] + w[1] * mesh.vertices[t[1]] + w[2] * mesh.vertices[t[2]];
      view->points.at<cv::Vec3d>(y, x) = cv::Vec3d(p.x(), p.y(), p.z());
      if (vertex_colours) {
        cv::Vec3f rgb(0, 0, 0);
        for (int k = 0; k < 3; ++k) {
          const auto& col = mesh.colors_rgb[t[k]];
          rgb += cv::Vec3f(col[2], col[1], col[0]) * static_cast<float>(w[k]);
        }
        z->base.at<cv::Vec3f>(y, x) = rgb;
      }
    }
  }
}

HeightRange CoveredHeights(const TopView& view, const Eigen::Vector3d& up_unit) {
  HeightRange r;
  r.low = std::numeric_limits<double>::infinity();
  r.high = -r.low;
  for (int y = 0; y < view.triangle.rows; ++y) {
    for (int x = 0; x < view.triangle.cols; ++x) {
      if (view.triangle.at<int>(y, x) < 0) continue;
      const cv::Vec3d& p = view.points.at<cv::Vec3d>(y, x);
      const double h = up_unit.dot(Eigen::Vector3d(p[0], p[1], p[2]));
      r.low = std::min(r.low, h), r.high = std::max(r.high, h);
    }
  }
  return r;
}

void ColourByHeightOrError(const TopView& view, const TopViewOptions& options,
                           const std::function<double(const Eigen::Vector3d&)>& distance,
                           const Eigen::Vector3d& up_unit, const HeightRange& heights, cv::Mat* base) {
  if (options.colour == TopViewColour::kMesh) return;
  const double low = heights.low, high = heights.high;
  ParallelFor(0, view.triangle.rows, 8, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      for (int x = 0; x < view.triangle.cols; ++x) {
        if (view.triangle.at<int>(y, x) < 0) continue;
        const cv::Vec3d& q = view.points.at<cv::Vec3d>(y, x);
        const Eigen::Vector3d p(q[0], q[1], q[2]);
        base->at<cv::Vec3f>(y, x) =
            options.colour == TopViewColour::kHeight
                ? HeightColour(high > low ? (up_unit.dot(p) - low) / (high - low) : 0.5)
                : kErrorColours[ErrorBin(distance(p), options.error_bins_m)];
      }
    }
  });
}

cv::Mat ShadeImage(const Mesh& mesh, const Projection& proj, const TopView& view, const cv::Mat& base) {
  const Eigen::Vector3d light = (-proj.into + 0.5 * proj.right + 0.3 * proj.image_up).normalized();
  cv::Mat image(view.triangle.rows, view.triangle.cols, CV_8UC3, cv::Scalar(kBackground));
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const int ti = view.triangle.at<int>(y, x);
      if (ti < 0) continue;
      const auto& t = mesh.triangles[ti];
      const Eigen::Vector3d& a = mesh.vertices[t[0]];
      const Eigen::Vector3d n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).normalized();
      const float shade = static_cast<float>(0.35 + 0.65 * std::abs(n.dot(light)));
      const cv::Vec3f c = base.at<cv::Vec3f>(y, x) * shade;
      // Never pure white, so that covered pixels always differ from the background.
      image.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<std::uint8_t>(std::min(c[0], 250.0f)),
                                            cv::saturate_cast<std::uint8_t>(std::min(c[1], 250.0f)),
                                            cv::saturate_cast<std::uint8_t>(std::min(c[2], 250.0f)));
    }
  }
  return image;
}

void DrawTrack(const std::vector<Eigen::Vector3d>& track, TopView* view) {
  if (track.size() < 2) return;
  std::vector<cv::Point> line;
  for (const Eigen::Vector3d& c : track) {
    const Eigen::Vector2d px = view->ToPixel(c);
    line.emplace_back(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
  }
  cv::polylines(view->image, line, false, cv::Scalar(140, 40, 20), 2, cv::LINE_AA);
}

}  // namespace eval_internal

TopView RenderTopView(const Mesh& mesh, const Eigen::Vector3d& up, const TopViewOptions& options,
                      const std::function<double(const Eigen::Vector3d&)>& distance,
                      const std::vector<Eigen::Vector3d>& track) {
  using namespace eval_internal;
  options.Check();
  SEMAP_CHECK_OPTION(up.allFinite() && up.norm() > 0.0, "up", up.transpose(), "must be a non-zero direction");
  SEMAP_ASSERT(mesh.IsConsistent(), "inconsistent mesh");
  SEMAP_ASSERT(options.colour != TopViewColour::kError || distance,
               "colour by error needs a distance function");
  const Projection proj = MakeProjection(up, options);
  TopView view;
  const ViewSize size = FitView(ProjectedExtent(mesh, proj, track), proj, options, &view);
  ZBuffer z = EmptyRaster(size, &view);
  for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
    RasteriseTriangle(mesh, ti, proj.into, size.height, &view, &z);
  }
  const Eigen::Vector3d up_unit = up.normalized();
  const HeightRange heights = CoveredHeights(view, up_unit);
  ColourByHeightOrError(view, options, distance, up_unit, heights, &z.base);
  view.image = ShadeImage(mesh, proj, view, z.base);
  DrawTrack(track, &view);
  if (options.legend) DrawLegend(options, view.metres_per_px, heights.low, heights.high, view.image);
  return view;
}

}  // namespace semap
