#include "engine/eval/error_breakdown.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/core/check.h"

namespace semap {
namespace {

bool Increasing(const std::vector<double>& edges) {
  for (std::size_t i = 1; i < edges.size(); ++i) {
    if (!(edges[i] > edges[i - 1])) return false;
  }
  return !edges.empty() && std::isfinite(edges.back());
}

std::string RangeName(double low, double high, const char* unit) {
  char text[64];
  if (std::isinf(high)) {
    std::snprintf(text, sizeof(text), ">= %g %s", low, unit);
  } else {
    std::snprintf(text, sizeof(text), "%g-%g %s", low, high, unit);
  }
  return text;
}

}  // namespace

void ErrorBreakdownOptions::Check() const {
  SEMAP_CHECK_OPTION(Increasing(distance_edges_m), "distance_edges_m", distance_edges_m.size(),
                     "must be a non-empty list of increasing finite values");
  SEMAP_CHECK_OPTION(Increasing(triangle_area_edges_m2), "triangle_area_edges_m2",
                     triangle_area_edges_m2.size(), "must be a non-empty list of increasing finite values");
  SEMAP_CHECK_OPTION(large_error_m > 0.0, "large_error_m", large_error_m, "must be > 0");
  SEMAP_CHECK_OPTION(median_resolution_m > 0.0, "median_resolution_m", median_resolution_m, "must be > 0");
  SEMAP_CHECK_OPTION(
      median_range_m / median_resolution_m >= 1.0 && median_range_m / median_resolution_m <= 1e7,
      "median_range_m", median_range_m, "must hold 1 to 10^7 cells of median_resolution_m");
}

std::vector<double> TriangleAreas(const Mesh& mesh) {
  std::vector<double> areas(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    areas[i] = 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
  }
  return areas;
}

std::vector<int> TriangleLabels(const Mesh& mesh) {
  if (mesh.labels.size() != mesh.vertices.size()) return {};
  std::vector<int> labels(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Label a = mesh.labels[t[0]], b = mesh.labels[t[1]], c = mesh.labels[t[2]];
    labels[i] = (b == c && a != b) ? b : a;  // a when it is shared (or nothing is), else the pair b = c
  }
  return labels;
}

cv::Mat PixelClasses(const cv::Mat& frame_labels, const cv::Mat& triangle,
                     const std::vector<int>& triangle_labels) {
  SEMAP_ASSERT(triangle.type() == CV_32S);
  cv::Mat classes(triangle.size(), CV_32S, cv::Scalar(-1));
  if (!frame_labels.empty() && frame_labels.size() == triangle.size() && frame_labels.type() == CV_8U) {
    frame_labels.convertTo(classes, CV_32S);
    return classes;
  }
  if (triangle_labels.empty()) return classes;
  for (int y = 0; y < triangle.rows; ++y) {
    const int* t = triangle.ptr<int>(y);
    int* c = classes.ptr<int>(y);
    for (int x = 0; x < triangle.cols; ++x) {
      if (t[x] >= 0) c[x] = triangle_labels[static_cast<std::size_t>(t[x])];
    }
  }
  return classes;
}

std::vector<int> MovableClassIds(const ClassMap& class_map) {
  static const char* const kMovable[] = {"person", "rider", "car",        "truck",
                                         "bus",    "train", "motorcycle", "bicycle"};
  std::vector<int> ids;
  for (const char* name : kMovable) {
    const int id = class_map.FindByName(name);
    if (id >= 0) ids.push_back(id);
  }
  return ids;
}

cv::Mat WithoutMovable(const cv::Mat& reference, const cv::Mat& labels, const std::vector<int>& movable) {
  SEMAP_ASSERT(reference.type() == CV_32F && (labels.type() == CV_8U || labels.type() == CV_32S) &&
               labels.size() == reference.size());
  std::array<bool, 256> is_movable{};
  for (const int id : movable) {
    if (id >= 0 && id < 256) is_movable[std::size_t(id)] = true;
  }
  const auto movable_at = [&](int y, int x) {
    const int id = labels.type() == CV_8U ? int(labels.at<std::uint8_t>(y, x)) : labels.at<int>(y, x);
    return id >= 0 && id < 256 && is_movable[std::size_t(id)];
  };
  cv::Mat out = reference.clone();
  for (int y = 0; y < out.rows; ++y) {
    float* z = out.ptr<float>(y);
    for (int x = 0; x < out.cols; ++x) {
      if (movable_at(y, x)) z[x] = 0.0f;
    }
  }
  return out;
}

ErrorBreakdownAccumulator::ErrorBreakdownAccumulator(const DepthAccuracyOptions& accuracy,
                                                     const ErrorBreakdownOptions& options)
    : accuracy_(accuracy), options_(options) {
  accuracy_.Check();
  options_.Check();
  by_distance_.resize(options_.distance_edges_m.size());
  by_area_.resize(options_.triangle_area_edges_m2.size());
}

int ErrorBreakdownAccumulator::BinOf(const std::vector<double>& edges, double value) {
  // The last edge not above value; values below the first edge go to the first bin.
  const auto it = std::upper_bound(edges.begin(), edges.end(), value);
  return std::max(0, static_cast<int>(it - edges.begin()) - 1);
}

void ErrorBreakdownAccumulator::AddError(Cell& cell, double error) const {
  ++cell.compared;
  cell.sum_sq += error * error;
  cell.sum += error;
  const double magnitude = std::abs(error);
  if (magnitude > options_.large_error_m) ++cell.large;
  const auto cells =
      static_cast<std::size_t>(std::ceil(options_.median_range_m / options_.median_resolution_m));
  if (cell.histogram.empty()) cell.histogram.assign(cells + 1, 0);  // + the overflow cell
  const double k = std::floor(magnitude / options_.median_resolution_m);
  ++cell.histogram[k >= static_cast<double>(cells) ? cells : static_cast<std::size_t>(k)];
}

void ErrorBreakdownAccumulator::Add(const cv::Mat& reference, const cv::Mat& mesh, const cv::Mat& triangle,
                                    const std::vector<double>& triangle_area_m2, const cv::Mat& pixel_class) {
  SEMAP_ASSERT(reference.type() == CV_32F && mesh.type() == CV_32F && triangle.type() == CV_32S);
  SEMAP_ASSERT(reference.size() == mesh.size() && reference.size() == triangle.size());
  SEMAP_ASSERT(pixel_class.empty() ||
               (pixel_class.type() == CV_32S && pixel_class.size() == reference.size()));
  // Neighbouring pixels mostly share a class: one map look-up per change of class.
  int last_class = std::numeric_limits<int>::min();
  Cell* last_class_cell = nullptr;
  for (int y = 0; y < reference.rows; ++y) {
    const float* r = reference.ptr<float>(y);
    const float* m = mesh.ptr<float>(y);
    const int* t = triangle.ptr<int>(y);
    const int* c = pixel_class.empty() ? nullptr : pixel_class.ptr<int>(y);
    for (int x = 0; x < reference.cols; ++x) {
      if (!(r[x] >= accuracy_.min_depth_m && r[x] <= accuracy_.max_depth_m)) continue;
      const int label = c ? c[x] : -1;
      if (label != last_class) {
        last_class = label;
        last_class_cell = &by_class_[label];
      }
      Cell& by_class = *last_class_cell;
      Cell& by_distance = by_distance_[static_cast<std::size_t>(BinOf(options_.distance_edges_m, r[x]))];
      ++by_class.reference;
      ++by_distance.reference;
      if (!(m[x] > 0.0f) || !std::isfinite(m[x])) continue;  // a hole
      const double error = static_cast<double>(m[x]) - static_cast<double>(r[x]);
      AddError(by_class, error);
      AddError(by_distance, error);
      if (t[x] >= 0) {
        SEMAP_ASSERT(static_cast<std::size_t>(t[x]) < triangle_area_m2.size());
        Cell& by_area = by_area_[static_cast<std::size_t>(
            BinOf(options_.triangle_area_edges_m2, triangle_area_m2[static_cast<std::size_t>(t[x])]))];
        ++by_area.reference;
        AddError(by_area, error);
      }
    }
  }
}

ErrorBin ErrorBreakdownAccumulator::Figures(const Cell& cell) const {
  ErrorBin b;
  b.reference_pixels = cell.reference;
  b.compared_pixels = cell.compared;
  b.large_pixels = cell.large;
  if (cell.reference > 0)
    b.completeness = static_cast<double>(cell.compared) / static_cast<double>(cell.reference);
  if (cell.compared == 0) return b;
  const auto n = static_cast<double>(cell.compared);
  b.rmse_m = std::sqrt(cell.sum_sq / n);
  b.mean_error_m = cell.sum / n;
  b.share_large = static_cast<double>(cell.large) / n;
  // The (n / 2)-th smallest |error| (0-based, as DepthAccuracy's median), at the centre of its cell.
  const auto wanted = static_cast<std::uint64_t>(cell.compared / 2);
  std::uint64_t seen = 0;
  for (std::size_t k = 0; k < cell.histogram.size(); ++k) {
    seen += cell.histogram[k];
    if (seen > wanted) {
      b.median_abs_m = k + 1 == cell.histogram.size()
                           ? options_.median_range_m
                           : (static_cast<double>(k) + 0.5) * options_.median_resolution_m;
      break;
    }
  }
  return b;
}

ErrorBreakdown ErrorBreakdownAccumulator::Result(const ClassMap& class_map) const {
  ErrorBreakdown result;
  result.large_error_m = options_.large_error_m;
  for (const auto& [label, cell] : by_class_) {
    if (label < 0) continue;
    ErrorBin b = Figures(cell);
    b.label = label;
    b.low = b.high = label;
    b.name = label <= 255 && class_map.Contains(static_cast<Label>(label))
                 ? class_map.Get(static_cast<Label>(label)).name
                 : "label " + std::to_string(label);
    result.by_class.push_back(b);
  }
  if (const auto it = by_class_.find(-1); it != by_class_.end()) {
    ErrorBin b = Figures(it->second);
    b.name = "no class";
    result.by_class.push_back(b);
  }
  const auto ranges = [&](const std::vector<double>& edges, const std::vector<Cell>& cells,
                          const char* unit) {
    std::vector<ErrorBin> bins;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      ErrorBin b = Figures(cells[i]);
      b.low = edges[i];
      b.high = i + 1 < edges.size() ? edges[i + 1] : std::numeric_limits<double>::infinity();
      b.name = RangeName(b.low, b.high, unit);
      bins.push_back(b);
    }
    return bins;
  };
  result.by_distance = ranges(options_.distance_edges_m, by_distance_, "m");
  result.by_triangle_area = ranges(options_.triangle_area_edges_m2, by_area_, "m2");
  return result;
}

}  // namespace semap
