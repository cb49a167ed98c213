// An HDL-64E-like spinning scanner ray-cast against the exact scene.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/sim/bvh.h"
#include "engine/sim/scene.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

// One scan in the scanner frame (x forward, y left, z up): x, y, z in metres and reflectance in [0, 1], as in
// KITTI's .bin files, plus the label of the surface each point lies on.
struct LidarScan {
  std::vector<Eigen::Vector4f> points_velo;
  std::vector<Label> labels;
};

// Beams evenly spaced in elevation between lidar_bottom_deg and lidar_top_deg, lidar_azimuth_steps rays per
// beam over 360 degrees, the whole scan taken at the frame's pose (no motion distortion). Range noise is
// Gaussian (lidar_range_noise_m), seeded per frame. Holds a reference to the BVH. Scan() is thread-safe.
class LidarScanner {
 public:
  LidarScanner(const Scene& scene, const TriangleBvh& bvh, const SynthOptions& options);

  LidarScan Scan(const Pose3d& scene_from_velo, std::uint64_t noise_seed) const;

 private:
  const Scene& scene_;
  const TriangleBvh& bvh_;
  SynthOptions options_;
};

}  // namespace semap::sim
