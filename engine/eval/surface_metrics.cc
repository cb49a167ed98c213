#include "engine/eval/surface_metrics.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "engine/core/check.h"
#include "engine/core/parallel.h"

namespace semap {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 ToPoint(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

std::vector<Triangle> Triangles(const Mesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.num_triangles());
  for (const auto& t : mesh.triangles) {
    const Triangle tri(ToPoint(mesh.vertices[t[0]]), ToPoint(mesh.vertices[t[1]]),
                       ToPoint(mesh.vertices[t[2]]));
    if (!tri.is_degenerate()) out.push_back(tri);
  }
  return out;
}

double TriangleArea(const Mesh& mesh, const std::array<std::uint32_t, 3>& t) {
  const Eigen::Vector3d& a = mesh.vertices[t[0]];
  return 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
}

// The distance of each sample to the surface, in parallel (each slot written by one thread).
std::vector<double> Distances(const SurfaceDistance& distance, const std::vector<Eigen::Vector3d>& samples) {
  std::vector<double> distances(samples.size());
  ParallelFor<std::size_t>(0, samples.size(), 1024, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) distances[i] = distance(samples[i]);
  });
  return distances;
}

// Share of `distances` within `threshold`, and their mean (summed in order: the same figures on any thread
// count).
std::pair<double, double> Coverage(const std::vector<double>& distances, double threshold) {
  if (distances.empty()) return {0.0, 0.0};
  std::int64_t within = 0;
  double sum = 0.0;
  for (const double d : distances) {
    sum += d;
    within += d <= threshold ? 1 : 0;
  }
  return {double(within) / double(distances.size()), sum / double(distances.size())};
}

}  // namespace

struct SurfaceDistance::Tree {
  std::vector<Triangle> triangles;
  AabbTree tree;
};

SurfaceDistance::SurfaceDistance(const Mesh& surface) : tree_(std::make_unique<Tree>()) {
  tree_->triangles = Triangles(surface);
  SEMAP_ASSERT(!tree_->triangles.empty(), "the surface has no triangle");
  tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
  // Built here, not lazily on the first query, so that queries from several threads only read.
  tree_->tree.build();
  tree_->tree.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

double SurfaceDistance::operator()(const Eigen::Vector3d& p) const {
  return std::sqrt(tree_->tree.squared_distance(ToPoint(p)));
}

void SurfaceMetricsOptions::Check() const {
  SEMAP_CHECK_OPTION(std::isfinite(threshold_m) && threshold_m > 0.0, "threshold_m", threshold_m,
                     "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(near_m) && near_m > 0.0, "near_m", near_m, "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(far_m) && far_m > near_m, "far_m", far_m, "must be finite and > near_m");
  SEMAP_CHECK_OPTION(area_samples >= 1, "area_samples", area_samples, "must be >= 1");
  for (std::size_t k = 0; k < completeness_depth_edges_m.size(); ++k) {
    const double edge = completeness_depth_edges_m[k];
    SEMAP_CHECK_OPTION(std::isfinite(edge) && edge > (k == 0 ? 0.0 : completeness_depth_edges_m[k - 1]),
                       "completeness_depth_edges_m", edge, "must be finite, > 0 and increasing");
  }
}

double SurfaceArea(const Mesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) area += TriangleArea(mesh, t);
  return area;
}

std::vector<Eigen::Vector3d> SampleSurface(const Mesh& mesh, int count, std::uint64_t seed) {
  std::vector<double> cumulative;  // cumulative[i] = area of triangles 0..i
  cumulative.reserve(mesh.num_triangles());
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    total += TriangleArea(mesh, t);
    cumulative.push_back(total);
  }
  std::vector<Eigen::Vector3d> samples;
  if (!(total > 0.0) || count <= 0) return samples;
  samples.reserve(static_cast<std::size_t>(count));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < count; ++k) {
    const double target = (double(k) + uniform(rng)) / double(count) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const std::size_t i = std::min<std::size_t>(it - cumulative.begin(), cumulative.size() - 1);
    const auto& t = mesh.triangles[i];
    // A uniform point of the triangle (Osada et al. 2002): sqrt of the first number, or it clusters at a.
    const double s = std::sqrt(uniform(rng));
    const double r = uniform(rng);
    samples.push_back((1.0 - s) * mesh.vertices[t[0]] + s * (1.0 - r) * mesh.vertices[t[1]] +
                      s * r * mesh.vertices[t[2]]);
  }
  return samples;
}

SurfaceMetrics CompareSurfaces(const Mesh& reconstruction, const Mesh& truth,
                               const std::vector<Eigen::Vector3d>& truth_samples,
                               const SurfaceMetricsOptions& options,
                               const std::vector<double>& truth_sample_depths_m) {
  options.Check();
  SEMAP_ASSERT(truth_sample_depths_m.empty() || truth_sample_depths_m.size() == truth_samples.size(),
               "one depth per truth sample, or none");
  const SurfaceDistance to_truth(truth);
  SurfaceMetrics m;
  m.threshold_m = options.threshold_m;
  m.near_m = options.near_m;
  m.far_m = options.far_m;
  m.truth_samples = std::int64_t(truth_samples.size());

  // By area.
  m.area_m2 = SurfaceArea(reconstruction);
  const std::vector<Eigen::Vector3d> area_samples =
      SampleSurface(reconstruction, options.area_samples, options.seed);
  m.area_samples = std::int64_t(area_samples.size());
  if (!area_samples.empty()) {
    const std::vector<double> distances = Distances(to_truth, area_samples);
    std::int64_t within_near = 0, beyond_far = 0;
    for (const double d : distances) {
      within_near += d <= options.near_m ? 1 : 0;
      beyond_far += d > options.far_m ? 1 : 0;
    }
    const double n = double(area_samples.size());
    std::tie(m.accuracy, m.mean_distance_m) = Coverage(distances, options.threshold_m);
    m.area_within_near = double(within_near) / n;
    m.area_beyond_near = double(m.area_samples - within_near) / n;
    m.area_beyond_far = double(beyond_far) / n;
  }

  // Per vertex and centroid.
  std::vector<Eigen::Vector3d> samples(reconstruction.vertices.begin(), reconstruction.vertices.end());
  for (const auto& t : reconstruction.triangles) {
    samples.push_back(
        (reconstruction.vertices[t[0]] + reconstruction.vertices[t[1]] + reconstruction.vertices[t[2]]) /
        3.0);
  }
  m.vertex_samples = std::int64_t(samples.size());
  std::tie(m.vertex_accuracy, m.vertex_mean_distance_m) =
      Coverage(Distances(to_truth, samples), options.threshold_m);

  const bool by_depth = !truth_sample_depths_m.empty();
  const auto& edges = options.completeness_depth_edges_m;
  const auto band_of = [&edges](double depth_m) {
    return std::size_t(std::upper_bound(edges.begin(), edges.end(), depth_m) - edges.begin());
  };
  if (by_depth) {
    for (std::size_t k = 0; k <= edges.size(); ++k) {
      m.completeness_by_depth.push_back(
          {k == 0 ? 0.0 : edges[k - 1],
           k < edges.size() ? edges[k] : std::numeric_limits<double>::infinity()});
    }
  }
  if (!Triangles(reconstruction).empty() && !truth_samples.empty()) {
    const std::vector<double> distances = Distances(SurfaceDistance(reconstruction), truth_samples);
    std::tie(m.completeness, m.mean_completeness_m) = Coverage(distances, options.threshold_m);
    std::vector<std::int64_t> band_within(m.completeness_by_depth.size(), 0);
    for (std::size_t i = 0; by_depth && i < distances.size(); ++i) {
      const std::size_t band = band_of(truth_sample_depths_m[i]);
      ++m.completeness_by_depth[band].samples;
      band_within[band] += distances[i] <= options.threshold_m ? 1 : 0;
    }
    for (std::size_t k = 0; k < band_within.size(); ++k) {
      auto& band = m.completeness_by_depth[k];
      band.completeness = band.samples > 0 ? double(band_within[k]) / double(band.samples) : 0.0;
    }
  } else if (by_depth) {
    for (const double depth_m : truth_sample_depths_m) ++m.completeness_by_depth[band_of(depth_m)].samples;
  }
  return m;
}

}  // namespace semap
