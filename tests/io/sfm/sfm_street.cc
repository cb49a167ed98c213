#include "tests/io/sfm/sfm_street.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace semap::test {
namespace {

// Camera x right, y down, z forward; the car's forward is world +y, up is world +z.
Pose3d KeyframePose(const StreetScene& scene, const SfmStreetOptions& o, int k) {
  Eigen::Matrix3d cam_axes;
  cam_axes.col(0) = Eigen::Vector3d::UnitX();
  cam_axes.col(1) = -Eigen::Vector3d::UnitZ();
  cam_axes.col(2) = Eigen::Vector3d::UnitY();
  const double yaw = o.yaw_wobble_rad * std::sin(0.7 * k);
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * cam_axes;
  world_from_cam.translation() = scene.CameraCenter(o.first_keyframe_y_m + k * o.keyframe_step_m);
  return world_from_cam;
}

}  // namespace

StreetScene SfmStreetScene(const SfmStreetOptions& o) {
  StreetScene scene;
  scene.length_m = o.first_keyframe_y_m + o.keyframes * o.keyframe_step_m + o.max_range_m + 20.0;
  return scene;
}

io::SfmReconstruction MakeSfmStreet(const StreetScene& scene, const SfmStreetOptions& o) {
  io::SfmReconstruction r;
  r.image_root = "images/";
  r.intrinsics.push_back(
      {1, "SIMPLE_PINHOLE", o.width_px, o.height_px, {o.focal_px, 0.5 * o.width_px, 0.5 * o.height_px}});
  const double f = o.focal_px, cx = 0.5 * o.width_px, cy = 0.5 * o.height_px;
  std::vector<Pose3d> cam_from_world;
  for (int k = 0; k < o.keyframes; ++k) {
    io::SfmView v;
    v.id = k + 1;
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", k);
    v.name = name;
    v.intrinsics_id = 1;
    v.world_from_cam = KeyframePose(scene, o, k);
    cam_from_world.push_back(v.world_from_cam.inverse(Eigen::Isometry));
    r.views.push_back(std::move(v));
  }

  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u_px(0.0, o.width_px), v_px(0.0, o.height_px);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int k = 0; k < o.keyframes; ++k) {
    const Eigen::Vector3d center = r.views[k].center_world();
    int added = 0;
    for (int attempt = 0; added < o.new_points_per_keyframe && attempt < 100 * o.new_points_per_keyframe;
         ++attempt) {
      const Eigen::Vector2d pixel(u_px(rng), v_px(rng));
      const Eigen::Vector3d dir =
          r.views[k].world_from_cam.linear() *
          Eigen::Vector3d((pixel.x() - cx) / f, (pixel.y() - cy) / f, 1.0).normalized();
      const auto hit = scene.Cast(center, dir);
      if (!hit || hit->first > o.max_range_m) continue;
      const Eigen::Vector3d truth = center + hit->first * dir;
      const auto point = static_cast<std::uint32_t>(r.num_points());
      Eigen::Vector3d p = truth;
      if (o.noise_m > 0.0) p += o.noise_m * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      r.point_ids.push_back(point + 1);
      r.points_world.push_back(p);
      if (o.labels) r.point_labels.push_back(hit->second);
      if (o.colours) r.point_colors_rgb.push_back({std::uint8_t(40 * hit->second % 256), 128, 200});
      r.observations.push_back({point, static_cast<std::uint32_t>(k), pixel});
      ++added;
      // Later keyframes that see the true point.
      for (int j = k + 1; j < o.keyframes && j <= k + o.max_track_keyframes; ++j) {
        const Eigen::Vector3d x = cam_from_world[j] * truth;
        if (x.z() <= 0.1) continue;
        const Eigen::Vector2d q(f * x.x() / x.z() + cx, f * x.y() / x.z() + cy);
        if (q.x() < 0.0 || q.x() >= o.width_px || q.y() < 0.0 || q.y() >= o.height_px) continue;
        const Eigen::Vector3d cj = r.views[j].center_world();
        const double range = (truth - cj).norm();
        if (range > o.max_range_m) continue;
        const auto first = scene.Cast(cj, (truth - cj) / range);
        if (!first || first->first < range - 1e-6) continue;  // occluded
        r.observations.push_back({point, static_cast<std::uint32_t>(j), q});
      }
    }
  }
  r.AssertConsistent();
  return r;
}

}  // namespace semap::test
