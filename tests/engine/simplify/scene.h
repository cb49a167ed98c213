// Synthetic labelled scenes for the simplification tests: a road plane, a box (car) standing on it and a
// building wall, observed by one camera. Exact geometry, seeded jitter.
#pragma once

#include <cmath>
#include <random>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"

namespace semap::test {

inline constexpr Label kRoad = 1;      // Cityscapes ids (ClassMap::Cityscapes): ground
inline constexpr Label kBuilding = 3;  // wall
inline constexpr Label kCar = 14;      // keep

struct SceneOptions {
  double spacing_m = 0.05;  // grid step of the surfaces
  double jitter_m = 0.01;   // uniform in-surface jitter
  double x_min = -4.0, x_max = 4.0;
  double y_min = -4.0, y_max = 4.0;
  bool with_box = true;   // box [0, 2] x [0, 1] x [0, 1], label car
  bool with_wall = true;  // wall x = x_max, z ∈ [0, 2], label building
  Eigen::Vector3d camera{-3.0, -3.0, 1.7};
  std::uint64_t seed = 7;
};

inline bool InBoxFootprint(double x, double y) { return x >= 0.0 && x <= 2.0 && y >= 0.0 && y <= 1.0; }

inline LabelledCloud MakeScene(const SceneOptions& o = {}) {
  LabelledCloud c;
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> j(-o.jitter_m, o.jitter_m);
  auto add = [&](const Eigen::Vector3d& p, Label l) {
    c.positions_world.push_back(p);
    c.labels.push_back(l);
    c.camera_index.push_back(0);
  };
  const double s = o.spacing_m;
  for (double x = o.x_min; x < o.x_max; x += s) {
    for (double y = o.y_min; y < o.y_max; y += s) {
      const Eigen::Vector3d p(x + j(rng), y + j(rng), 0.0);
      if (o.with_box && InBoxFootprint(p.x(), p.y())) continue;
      add(p, kRoad);
    }
  }
  if (o.with_box) {
    // Top and the four sides of the box.
    for (double x = 0.0; x <= 2.0; x += s) {
      for (double y = 0.0; y <= 1.0; y += s) add({x, y, 1.0}, kCar);
      for (double z = 0.0; z <= 1.0; z += s) {
        add({x, 0.0, z}, kCar);
        add({x, 1.0, z}, kCar);
      }
    }
    for (double y = 0.0; y <= 1.0; y += s) {
      for (double z = 0.0; z <= 1.0; z += s) {
        add({0.0, y, z}, kCar);
        add({2.0, y, z}, kCar);
      }
    }
  }
  if (o.with_wall) {
    for (double y = o.y_min; y < o.y_max; y += s) {
      for (double z = s; z < 2.0; z += s) add({o.x_max, y + j(rng), z + j(rng)}, kBuilding);
    }
  }
  c.camera_centers_world = {o.camera};
  c.camera_frame_ids = {0};
  return c;
}

// Distance on the ground from (x, y) to the box footprint rectangle (0 inside).
inline double DistanceToFootprint(double x, double y) {
  const double dx = std::max({0.0 - x, 0.0, x - 2.0});
  const double dy = std::max({0.0 - y, 0.0, y - 1.0});
  return std::hypot(dx, dy);
}

}  // namespace semap::test
