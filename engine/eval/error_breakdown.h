// Where the large depth errors come from: the per-pixel errors of the accuracy measure
// (engine/eval/depth_accuracy.h: same reference pixels, same depth range, error = mesh depth − reference
// depth) split three ways:
// - by class: the semantic class of the pixel (the dataset's label image when the frame has one, else
//   the label of the mesh triangle the pixel's ray hits first; "no class" when neither is known);
// - by reference distance: the reference depth (camera-frame z) in bins such as 0–5, 5–10, … m;
// - by triangle size: the area (m², in the world) of the mesh triangle the pixel's ray hits first.
// Each bin gives its count of compared pixels, RMSE, median |error|, mean error and the share of errors
// beyond large_error_m; class and distance bins also their reference pixels and completeness (a reference
// pixel with no mesh depth is a hole: it has no triangle, so the triangle bins count compared pixels only).
// The breakdown uses the strict protocol: every error counts, whatever DepthAccuracyOptions::max_abs_error_m.
#pragma once

#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/mesh.h"
#include "engine/eval/depth_accuracy.h"

namespace semap {

struct ErrorBreakdownOptions {
  // Lower edges of the reference-distance bins (m), increasing: bin i holds depths in [edge_i, edge_i+1), the
  // last bin [last edge, ∞). The depth range itself is DepthAccuracyOptions' (1–40 m by default).
  std::vector<double> distance_edges_m{0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 40.0};
  // Lower edges of the triangle-area bins (m²), increasing, the same way: a 1 dm² triangle is "0.01–0.1 m²".
  std::vector<double> triangle_area_edges_m2{0.0, 0.01, 0.1, 1.0, 10.0, 100.0};
  // An error beyond this (absolute, m) is large: the bound of the paper protocol.
  double large_error_m = kPaperMaxAbsErrorM;
  // The per-bin median comes from a histogram of |error| with cells this wide (m): exact to this.
  double median_resolution_m = 0.001;
  // Errors beyond this (m) share the histogram's last cell; a median there reads as this value (a lower
  // bound).
  double median_range_m = 100.0;
  void Check() const;
};

// One bin's figures (metres; shares in [0, 1]).
struct ErrorBin {
  std::string name;                   // "5-10 m", "Road", "0.1-1 m2", "no class"
  double low = 0.0, high = 0.0;       // distance / area bins: [low, high), high = +inf for the last one
  int label = -1;                     // class bins: the label id (−1 = no class)
  std::int64_t reference_pixels = 0;  // class and distance bins; = compared_pixels for triangle bins
  std::int64_t compared_pixels = 0;
  double completeness = 0.0;  // compared / reference
  double rmse_m = 0.0;
  double median_abs_m = 0.0;
  double mean_error_m = 0.0;  // signed: > 0 means the mesh is behind the reference
  double share_large = 0.0;   // share of the compared pixels with |error| > large_error_m
  std::int64_t large_pixels = 0;
};

struct ErrorBreakdown {
  double large_error_m = 0.0;
  std::vector<ErrorBin> by_class;     // classes in label order, "no class" last (only classes with pixels)
  std::vector<ErrorBin> by_distance;  // every bin, in order
  std::vector<ErrorBin> by_triangle_area;  // every bin, in order
};

// Area (m²) of each triangle of `mesh`, in triangle order.
std::vector<double> TriangleAreas(const Mesh& mesh);

// The label of each triangle of `mesh` from its vertex labels: the label two or three vertices share, else
// the first vertex's. Empty when the mesh has no labels.
std::vector<int> TriangleLabels(const Mesh& mesh);

// The class of each pixel (CV_32S, −1 = unknown): `frame_labels` (CV_8U) when it is non-empty and the size of
// `triangle`, else the label of the triangle hit (`triangle`: CV_32S indices, −1 = none; `triangle_labels` as
// TriangleLabels, empty = none known).
cv::Mat PixelClasses(const cv::Mat& frame_labels, const cv::Mat& triangle,
                     const std::vector<int>& triangle_labels);

// The classes of objects that move on a street, by name (person, rider, car, truck, bus, train, motorcycle,
// bicycle, as Cityscapes and the generated sequences name them): the ids `class_map` has of them.
std::vector<int> MovableClassIds(const ClassMap& class_map);

// `reference` (CV_32F depth, 0 = none) without the pixels whose label is in `movable`: the static scene, so
// that a map of what stays is not judged by objects that moved on. `labels`, of the reference's size: a
// frame's label image (CV_8U) or PixelClasses' classes (CV_32S, −1 = none).
cv::Mat WithoutMovable(const cv::Mat& reference, const cv::Mat& labels, const std::vector<int>& movable);

// Accumulates the breakdown over pixels and frames. Not thread-safe.
class ErrorBreakdownAccumulator {
 public:
  // Checks both options (throws InvalidOption).
  ErrorBreakdownAccumulator(const DepthAccuracyOptions& accuracy, const ErrorBreakdownOptions& options = {});
  // One camera: `reference` and `mesh` CV_32F depth maps (0 = none), `triangle` the CV_32S index of the
  // triangle hit (−1 = none; as RenderDepthAndTriangles), `triangle_area_m2` indexed by it, `pixel_class`
  // CV_32S (−1 = unknown) or empty (every pixel unknown). Sizes must agree (programmer error otherwise).
  void Add(const cv::Mat& reference, const cv::Mat& mesh, const cv::Mat& triangle,
           const std::vector<double>& triangle_area_m2, const cv::Mat& pixel_class);
  // Class names come from `class_map` (an id it does not know is named "label N").
  ErrorBreakdown Result(const ClassMap& class_map) const;

 private:
  struct Cell {
    std::int64_t reference = 0, compared = 0, large = 0;
    double sum_sq = 0.0, sum = 0.0;
    std::vector<std::uint32_t> histogram;  // |error| in cells of median_resolution_m, allocated on first use
  };
  void AddError(Cell& cell, double error) const;
  ErrorBin Figures(const Cell& cell) const;
  static int BinOf(const std::vector<double>& edges, double value);

  DepthAccuracyOptions accuracy_;
  ErrorBreakdownOptions options_;
  std::map<int, Cell> by_class_;
  std::vector<Cell> by_distance_;
  std::vector<Cell> by_area_;
};

}  // namespace semap
