#include "tests/engine/map/street_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "engine/core/depth_view.h"
#include "tests/engine/map/map_test_util.h"

namespace semap::test {
namespace {

constexpr Label kRoad = 1, kBuilding = 3, kCar = 14;

// Axis-aligned rectangle: coordinate `axis` fixed at `value`, the two others within [lo, hi].
struct Rect {
  int axis;
  double value;
  Eigen::Vector3d lo, hi;  // bounds (the fixed axis ignored)
  Label label;

  double Distance(const Eigen::Vector3d& p) const {
    Eigen::Vector3d q = p.cwiseMax(lo).cwiseMin(hi);
    q[axis] = value;
    return (p - q).norm();
  }
  std::optional<double> Hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    if (std::abs(d[axis]) < 1e-12) return std::nullopt;
    const double t = (value - o[axis]) / d[axis];
    if (t <= 1e-9) return std::nullopt;
    const Eigen::Vector3d p = o + t * d;
    for (int k = 0; k < 3; ++k) {
      if (k != axis && (p[k] < lo[k] || p[k] > hi[k])) return std::nullopt;
    }
    return t;
  }
};

std::vector<Rect> Surfaces(const StreetScene& s) {
  const double y0 = -10.0, y1 = s.length_m - 10.0, w = s.half_width_m, h = s.wall_height_m;
  const Eigen::Vector3d bmin = s.box_min, bmax = s.box_max;
  std::vector<Rect> r;
  r.push_back({2, 0.0, {-w, y0, 0}, {w, y1, 0}, kRoad});
  r.push_back({0, -w, {-w, y0, 0}, {-w, y1, h}, kBuilding});
  r.push_back({0, w, {w, y0, 0}, {w, y1, h}, kBuilding});
  for (int axis = 0; axis < 3; ++axis) {
    for (double value : {bmin[axis], bmax[axis]}) {
      if (axis == 2 && value == bmin[2]) continue;  // the bottom lies on the ground
      r.push_back({axis, value, bmin, bmax, kCar});
    }
  }
  return r;
}

}  // namespace

double StreetScene::Distance(const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Rect& r : Surfaces(*this)) best = std::min(best, r.Distance(p));
  return best;
}

std::optional<std::pair<double, Label>> StreetScene::Cast(const Eigen::Vector3d& origin,
                                                          const Eigen::Vector3d& dir) const {
  std::optional<std::pair<double, Label>> best;
  for (const Rect& r : Surfaces(*this)) {
    if (auto t = r.Hit(origin, dir); t && (!best || *t < best->first)) best = std::make_pair(*t, r.label);
  }
  return best;
}

LabelledCloud SampleStreet(const StreetScene& scene, const StreetSamplingOptions& o) {
  LabelledCloud cloud;
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double tan_x = std::tan(M_PI / 4.0), tan_z = std::tan(M_PI / 6.0);
  for (int c = 0; c < o.num_cameras; ++c) {
    const Eigen::Vector3d center = scene.CameraCenter(o.first_camera_y_m + c * o.camera_step_m);
    cloud.camera_centers_world.push_back(center);
    cloud.camera_frame_ids.push_back(c);
    for (int j = 0; j < o.rays_z; ++j) {
      for (int i = 0; i < o.rays_x; ++i) {
        // Pixel centres of a pinhole image (offset by half a pixel, so no ray is axis-aligned).
        const double u = ((i + 0.5) / o.rays_x * 2.0 - 1.0) * tan_x;
        const double v = ((j + 0.5) / o.rays_z * 2.0 - 1.0) * tan_z;
        const Eigen::Vector3d dir = Eigen::Vector3d(u, 1.0, v).normalized();
        const auto hit = scene.Cast(center, dir);
        if (!hit || hit->first > o.max_range_m) continue;
        Eigen::Vector3d p = center + hit->first * dir;
        if (o.noise_m > 0.0) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * o.noise_m;
        cloud.positions_world.push_back(p);
        cloud.labels.push_back(hit->second);
        cloud.colors_rgb.push_back({std::uint8_t(40 * hit->second % 256), 128, 200});
        cloud.camera_index.push_back(std::uint32_t(c));
      }
    }
  }
  return cloud;
}

// One frame of the analytic street seen by a pinhole camera at y_m looking +y (±45° wide): its depth view
// (rays that hit nothing are sky: free to the far range) and a point at every stride-th pixel.
LabelledCloud StreetDepthFrame(const StreetScene& scene, double y_m, int stride) {
  constexpr int kWidth = 96, kHeight = 64;
  constexpr double kFocal = 48.0, kMaxDepth = 30.0;
  auto view = PinholeDepthView(kWidth, kHeight, kFocal, kMaxDepth);
  Eigen::Matrix3d world_from_cam_rotation;  // camera x right, y down, z forward → world x, −z, y
  world_from_cam_rotation << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  view->world_from_cam.linear() = world_from_cam_rotation;
  view->world_from_cam.translation() = scene.CameraCenter(y_m);
  LabelledCloud cloud;
  cloud.camera_centers_world.push_back(scene.CameraCenter(y_m));
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const Eigen::Vector3d ray_cam((u - view->intrinsics.cx_px) / kFocal,
                                    (v - view->intrinsics.cy_px) / kFocal, 1.0);
      const Eigen::Vector3d dir = (world_from_cam_rotation * ray_cam).normalized();
      const auto hit = scene.Cast(scene.CameraCenter(y_m), dir);
      const double depth = hit ? hit->first / ray_cam.norm() : 0.0;
      if (!hit || depth > kMaxDepth) {
        view->depth_m.at<float>(v, u) = kFreeToFarRange;
        continue;
      }
      view->depth_m.at<float>(v, u) = float(depth);
      if (u % stride || v % stride) continue;
      cloud.positions_world.push_back(scene.CameraCenter(y_m) + hit->first * dir);
      cloud.labels.push_back(hit->second);
      cloud.camera_index.push_back(0);
    }
  }
  cloud.camera_views.push_back(std::move(view));
  return cloud;
}

}  // namespace semap::test
