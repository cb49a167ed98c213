// Helpers shared by the map tests: mesh-to-ground-truth error and simple clouds.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/depth_view.h"
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
inline SurfaceError MeshError(const Mesh& mesh,
                              const std::function<double(const Eigen::Vector3d&)>& distance) {
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

// Distance along origin + t·dir (t > 0) to the first triangle of `mesh` hit (Möller–Trumbore), if any.
inline std::optional<double> RayMeshDistance(const Mesh& mesh, const Eigen::Vector3d& origin,
                                             const Eigen::Vector3d& dir) {
  std::optional<double> best;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d e1 = mesh.vertices[t[1]] - a, e2 = mesh.vertices[t[2]] - a;
    const Eigen::Vector3d h = dir.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(h) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = dir.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double dist = e2.dot(q) / det;
    if (dist > 1e-9 && (!best || dist < *best)) best = dist;
  }
  return best;
}

// A pinhole camera's depth view, world = camera frame: width × height px, focal focal_px, the principal
// point at the image centre, a 0.5 m baseline, far range max_depth_m, and no depth anywhere yet (all 0).
inline std::shared_ptr<DepthView> PinholeDepthView(int width_px, int height_px, double focal_px,
                                                   double max_depth_m) {
  auto view = std::make_shared<DepthView>();
  view->intrinsics.fx_px = view->intrinsics.fy_px = focal_px;
  view->intrinsics.cx_px = width_px / 2.0;
  view->intrinsics.cy_px = height_px / 2.0;
  view->intrinsics.baseline_m = 0.5;
  view->intrinsics.width_px = width_px;
  view->intrinsics.height_px = height_px;
  view->max_depth_m = max_depth_m;
  view->depth_m = cv::Mat::zeros(height_px, width_px, CV_32F);
  return view;
}

}  // namespace semap::test
