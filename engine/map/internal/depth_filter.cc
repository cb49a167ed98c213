#include "engine/map/internal/depth_filter.h"

#include <algorithm>
#include <cmath>

namespace semap::map_internal {

void DepthFilter::Start(const Eigen::Vector3d& x_world, double sigma_m) {
  weight = 1.0 / (sigma_m * sigma_m);
  weighted_sum = weight * x_world;
  inliers = 1;
  outliers = 0;
}

void DepthFilter::AddInlier(const Eigen::Vector3d& x_world, double sigma_m) {
  const double w = 1.0 / (sigma_m * sigma_m);
  weight += w;
  weighted_sum += w * x_world;
  ++inliers;
}

Sighting ObserveVertex(const Eigen::Vector3d& vertex_world, const VotingView& view, double disparity_sigma_px,
                       double gate_sigmas, DepthFilter* filter) {
  const DepthView& v = *view.view;
  const Eigen::Vector3d p = view.ToCamera(vertex_world);
  if (!(p.z() > 0.0) || p.z() >= v.max_depth_m) return Sighting::kNone;
  const PixelQuad quad = QuadAround(v, v.intrinsics.Project(p));
  if (!quad.inside) return Sighting::kNone;
  // The vertex's and the view's noise, in depth.
  const double vertex_sigma_m = filter->Sigma() * p.z() / p.norm();
  float nearest_m = kFreeToFarRange, farthest_m = 0.0f;
  int with_depth = 0;
  for (const float d : quad.depth_m) {
    if (d == 0.0f) continue;  // no depth there: no evidence from that pixel
    ++with_depth;
    nearest_m = std::min(nearest_m, d);
    farthest_m = std::max(farthest_m, d);
  }
  if (with_depth == 0) return Sighting::kNone;
  const auto gate_m = [&](double depth_m) {
    return gate_sigmas * std::hypot(view.DepthSigma(depth_m, disparity_sigma_px), vertex_sigma_m);
  };
  // Seen through: every pixel around saw beyond the gate (or sky).
  if (nearest_m == kFreeToFarRange || nearest_m - p.z() > gate_m(nearest_m)) {
    ++filter->outliers;
    return Sighting::kOutlier;
  }
  if (quad.AllValid() && farthest_m - nearest_m <= gate_m(farthest_m)) {
    const double seen_m = quad.InterpolatedDepth();
    if (std::abs(seen_m - p.z()) > gate_m(seen_m)) return Sighting::kNone;  // occluded
    const Eigen::Vector3d camera = v.world_from_cam.translation();
    // The sighting's σ is taken at the vertex's depth, not at the seen one: weights that depend on the
    // sighting's own noise (σ ∝ D²) would favour the nearer draws and bias the estimate towards the camera.
    filter->AddInlier(camera + (vertex_world - camera) * (seen_m / p.z()),
                      AlongRaySigma(view, p, disparity_sigma_px));
    return Sighting::kInlier;
  }
  // A depth edge or missing pixels: a sighting within the gate at one of the pixels counts, without moving.
  for (const float d : quad.depth_m) {
    if (PixelQuad::Valid(d) && std::abs(d - p.z()) <= gate_m(d)) {
      ++filter->inliers;
      return Sighting::kInlier;
    }
  }
  return Sighting::kNone;
}

}  // namespace semap::map_internal
