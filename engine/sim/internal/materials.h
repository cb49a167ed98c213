// Procedural surface colours (solid textures evaluated at the 3D surface point) and the sky.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "engine/sim/scene.h"
#include "engine/sim/synth_options.h"

namespace semap::sim::sim_internal {

// What the texture functions need to know about the world, as SynthOptions sets it (its defaults are declared
// there only).
struct TextureContext {
  explicit TextureContext(const SynthOptions& options)
      : seed(options.seed), block_pitch_m(options.block_pitch_m), road_width_m(options.road_width_m) {}
  std::uint64_t seed;
  double block_pitch_m;  // road markings follow the street centre lines
  double road_width_m;
};

// Albedo (display-referred RGB in [0, 1]) of `material` at scene point `p` on a surface with normal `n`.
// `footprint_m` is the size of one pixel on the surface: detail finer than two pixels fades to its mean.
Eigen::Vector3f Albedo(const TextureContext& ctx, Material material, std::uint32_t object_id,
                       const Eigen::Vector3d& p, const Eigen::Vector3f& n, double footprint_m);

// Sky radiance (RGB in [0, 1]) along the unit scene direction `d` (z up).
Eigen::Vector3f SkyColor(const TextureContext& ctx, const Eigen::Vector3d& d);

// Reflectance in [0, 1] of a material as seen by the scanner.
float LidarReflectance(Material material);

}  // namespace semap::sim::sim_internal
