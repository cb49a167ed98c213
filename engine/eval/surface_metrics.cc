#include "engine/eval/surface_metrics.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 ToPoint(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

std::vector<Triangle> Triangles(const Mesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.num_triangles());
  for (const auto& t : mesh.triangles) {
    const Triangle tri(ToPoint(mesh.vertices[t[0]]), ToPoint(mesh.vertices[t[1]]), ToPoint(mesh.vertices[t[2]]));
    if (!tri.is_degenerate()) out.push_back(tri);
  }
  return out;
}

// Share of `samples` within `threshold` of the tree's surface, and their mean distance.
std::pair<double, double> Coverage(const Tree& tree, const std::vector<Eigen::Vector3d>& samples, double threshold) {
  if (samples.empty()) return {0.0, 0.0};
  std::int64_t within = 0;
  double sum = 0.0;
  for (const Eigen::Vector3d& p : samples) {
    const double d = std::sqrt(tree.squared_distance(ToPoint(p)));
    sum += d;
    within += d <= threshold ? 1 : 0;
  }
  return {double(within) / double(samples.size()), sum / double(samples.size())};
}

}  // namespace

void SurfaceMetricsOptions::Check() const {
  SEMAP_CHECK_OPTION(std::isfinite(threshold_m) && threshold_m > 0.0, "threshold_m", threshold_m,
                     "must be finite and > 0");
}

SurfaceMetrics CompareSurfaces(const Mesh& reconstruction, const Mesh& truth,
                               const std::vector<Eigen::Vector3d>& truth_samples,
                               const SurfaceMetricsOptions& options) {
  options.Check();
  const std::vector<Triangle> truth_triangles = Triangles(truth);
  SEMAP_ASSERT(!truth_triangles.empty(), "the true surface has no triangle");
  SurfaceMetrics m;
  m.truth_samples = std::int64_t(truth_samples.size());

  std::vector<Eigen::Vector3d> samples(reconstruction.vertices.begin(), reconstruction.vertices.end());
  for (const auto& t : reconstruction.triangles) {
    samples.push_back((reconstruction.vertices[t[0]] + reconstruction.vertices[t[1]] +
                       reconstruction.vertices[t[2]]) / 3.0);
  }
  m.reconstruction_samples = std::int64_t(samples.size());
  const Tree truth_tree(truth_triangles.begin(), truth_triangles.end());
  std::tie(m.accuracy, m.mean_accuracy_m) = Coverage(truth_tree, samples, options.threshold_m);

  const std::vector<Triangle> reconstruction_triangles = Triangles(reconstruction);
  if (!reconstruction_triangles.empty()) {
    const Tree tree(reconstruction_triangles.begin(), reconstruction_triangles.end());
    std::tie(m.completeness, m.mean_completeness_m) = Coverage(tree, truth_samples, options.threshold_m);
  }
  return m;
}

}  // namespace semap
