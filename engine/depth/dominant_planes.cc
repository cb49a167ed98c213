#include "engine/depth/dominant_planes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "engine/core/plane_fit.h"

namespace semap {
namespace {

// RANSAC's adaptive stop: the chance of drawing an all-inlier sample at least once.
constexpr double kRansacConfidence = 0.999;
constexpr std::uint64_t kSeed = 1;

// The world points of the pixels of `role` with a depth.
std::vector<Eigen::Vector3d> RolePoints(const cv::Mat& depth_m, const cv::Mat& labels,
                                        const PlaneSweepView& view, const ClassMap& classes, ClassRole role) {
  const Eigen::Matrix3d K_inverse = view.K.inverse();
  const double sx = static_cast<double>(labels.cols) / depth_m.cols;
  const double sy = static_cast<double>(labels.rows) / depth_m.rows;
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_m.ptr<float>(v);
    const int lv = std::min(labels.rows - 1, static_cast<int>((v + 0.5) * sy));
    const std::uint8_t* l = labels.ptr<std::uint8_t>(lv);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!(z[u] > 0.0f) || !std::isfinite(z[u])) continue;
      const int lu = std::min(labels.cols - 1, static_cast<int>((u + 0.5) * sx));
      if (classes.Role(l[lu]) != role) continue;
      points.push_back(view.world_from_cam * (z[u] * (K_inverse * Eigen::Vector3d(u, v, 1.0))));
    }
  }
  return points;
}

}  // namespace

std::vector<SweepDirection> DominantDirections(const cv::Mat& depth_m, const cv::Mat& labels,
                                               const PlaneSweepView& view, const ClassMap& classes,
                                               const DominantPlaneOptions& options) {
  std::vector<SweepDirection> directions;
  if (depth_m.empty() || labels.empty() || depth_m.type() != CV_32F || labels.type() != CV_8UC1)
    return directions;
  std::mt19937_64 rng(kSeed);
  for (const ClassRole role : {ClassRole::kGround, ClassRole::kWall}) {
    const std::vector<Eigen::Vector3d> points = RolePoints(depth_m, labels, view, classes, role);
    if (static_cast<int>(points.size()) < options.min_points) continue;
    std::vector<std::uint32_t> all(points.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    const std::optional<Plane> plane = FitPlaneRansac(points, all, options.inlier_m, options.iterations,
                                                      options.max_points, kRansacConfidence, rng);
    if (!plane) continue;
    std::size_t inliers = 0;
    for (const Eigen::Vector3d& p : points) inliers += std::abs(plane->SignedDistance(p)) <= options.inlier_m;
    if (static_cast<double>(inliers) < options.min_inlier_share * static_cast<double>(points.size()))
      continue;
    // Plane n·X + offset = 0 is the sweep's nᵀX = c with c = −offset.
    const double c = -plane->offset;
    const double distance_m = std::abs(plane->normal.dot(view.world_from_cam.translation()) - c);
    if (!(distance_m > 0.0)) continue;
    SweepDirection d;
    d.normal_world = plane->normal;
    d.min_offset_m = c - options.offset_fraction * distance_m;
    d.max_offset_m = c + options.offset_fraction * distance_m;
    directions.push_back(d);
  }
  return directions;
}

}  // namespace semap
