// Helpers shared by the map tests: mesh-to-ground-truth error and simple clouds.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>
#include <functional>

#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh.h"

namespace semap::test {

struct SurfaceError {
  double mean_m = 0.0;
  double rmse_m = 0.0;
  double max_m = 0.0;
  double median_m = 0.0;
  std::size_t samples = 0;
};

// Distance to the ground truth sampled on every triangle (its vertices, edge midpoints and centroid),
// weighted equally per sample.
inline SurfaceError MeshError(const Mesh& mesh, const std::function<double(const Eigen::Vector3d&)>& distance) {
  SurfaceError e;
  double sum = 0.0, sum_sq = 0.0;
  std::vector<double> all;
  auto sample = [&](const Eigen::Vector3d& p) {
    const double d = distance(p);
    all.push_back(d);
    sum += d;
    sum_sq += d * d;
    e.max_m = std::max(e.max_m, d);
    ++e.samples;
  };
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    sample((a + b + c) / 3.0);
    sample((a + b) / 2.0);
    sample((b + c) / 2.0);
    sample((a + c) / 2.0);
  }
  if (e.samples > 0) {
    e.mean_m = sum / e.samples;
    e.rmse_m = std::sqrt(sum_sq / e.samples);
    std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
    e.median_m = all[all.size() / 2];
  }
  return e;
}

}  // namespace semap::test
