#include "engine/sim/lidar_scanner.h"

#include <cmath>

#include "engine/sim/internal/materials.h"
#include "engine/sim/internal/random.h"

namespace semap::sim {

LidarScanner::LidarScanner(const Scene& scene, const TriangleBvh& bvh, const SynthOptions& options)
    : scene_(scene), bvh_(bvh), options_(options) {
  options_.Check();
}

LidarScan LidarScanner::Scan(const Pose3d& scene_from_velo, std::uint64_t noise_seed) const {
  const SynthOptions& o = options_;
  LidarScan scan;
  scan.points_velo.reserve(static_cast<size_t>(o.lidar_beams) * o.lidar_azimuth_steps);
  scan.labels.reserve(scan.points_velo.capacity());
  const Eigen::Matrix3d r = scene_from_velo.linear();
  const Eigen::Vector3d origin = scene_from_velo.translation();
  sim_internal::Rng rng(noise_seed);
  for (int a = 0; a < o.lidar_azimuth_steps; ++a) {
    // Spin order as the real sensor: azimuth outer, beams inner; start facing backwards (KITTI's cut).
    const double az = M_PI - 2.0 * M_PI * a / o.lidar_azimuth_steps;
    for (int b = 0; b < o.lidar_beams; ++b) {
      const double el_deg = o.lidar_beams == 1 ? o.lidar_top_deg
                                               : o.lidar_top_deg - (o.lidar_top_deg - o.lidar_bottom_deg) *
                                                                       b / (o.lidar_beams - 1);
      const double el = el_deg * M_PI / 180.0;
      const Eigen::Vector3d dir_velo(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const double noise = o.lidar_range_noise_m > 0.0 ? o.lidar_range_noise_m * rng.Normal() : 0.0;
      const auto hit = bvh_.Intersect(origin, r * dir_velo, o.lidar_min_range_m, o.lidar_max_range_m);
      if (!hit) continue;
      const double range = hit->t + noise;
      if (range <= 0.0) continue;
      const Eigen::Vector3d p = range * dir_velo;
      const float refl = sim_internal::LidarReflectance(scene_.materials[hit->triangle]);
      scan.points_velo.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                    static_cast<float>(p.z()), refl);
      scan.labels.push_back(scene_.labels[hit->triangle]);
    }
  }
  return scan;
}

}  // namespace semap::sim
