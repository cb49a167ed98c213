#include "tests/engine/depth/sweep_scene.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace semap::sweep_scene {

Eigen::Matrix3d TestK() {
  Eigen::Matrix3d K;
  K << kFocalPx, 0.0, kWidth / 2.0 - 0.5, 0.0, kFocalPx, kHeight / 2.0 + 0.5, 0.0, 0.0, 1.0;
  return K;
}

cv::Mat RandomTexture(int size, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat noise(size, size, CV_32F);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.2);
  cv::normalize(noise, noise, 20.0, 235.0, cv::NORM_MINMAX);
  return noise;
}

std::pair<double, double> Trace(const std::vector<TexturedPlane>& scene, const Eigen::Vector3d& centre,
                                const Eigen::Vector3d& direction) {
  std::pair<double, double> hit{std::numeric_limits<double>::infinity(), 0.0};
  for (const TexturedPlane& p : scene) {
    const Eigen::Vector3d normal = p.axis_s.cross(p.axis_t);
    const double along = normal.dot(direction);
    if (std::abs(along) < 1e-12) continue;
    const double lambda = normal.dot(p.point_world - centre) / along;
    if (!(lambda > 0.0) || lambda >= hit.first) continue;
    const Eigen::Vector3d x = centre + lambda * direction - p.point_world;
    const double tx = x.dot(p.axis_s) * p.texels_per_m, ty = x.dot(p.axis_t) * p.texels_per_m;
    if (tx < 0.0 || ty < 0.0 || tx > p.texture.cols - 2 || ty > p.texture.rows - 2) continue;
    const int x0 = int(tx), y0 = int(ty);
    const double ax = tx - x0, ay = ty - y0;
    const auto at = [&](int dy, int dx) { return double(p.texture.at<float>(y0 + dy, x0 + dx)); };
    const double grey =
        (1 - ay) * ((1 - ax) * at(0, 0) + ax * at(0, 1)) + ay * ((1 - ax) * at(1, 0) + ax * at(1, 1));
    hit = {lambda, grey};
  }
  return hit;
}

PlaneSweepView Render(const std::vector<TexturedPlane>& scene, const Pose3d& world_from_cam,
                      cv::Mat* depth_m) {
  PlaneSweepView view;
  view.K = TestK();
  view.world_from_cam = world_from_cam;
  cv::Mat grey(kHeight, kWidth, CV_32F);
  if (depth_m != nullptr) *depth_m = cv::Mat::zeros(kHeight, kWidth, CV_32F);
  const Eigen::Matrix3d K_inverse = view.K.inverse();
  const Eigen::Vector3d centre = world_from_cam.translation();
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      double sum = 0.0;
      for (double dv : {-0.25, 0.25})
        for (double du : {-0.25, 0.25})
          sum += Trace(scene, centre,
                       world_from_cam.linear() * (K_inverse * Eigen::Vector3d(u + du, v + dv, 1.0)))
                     .second;
      grey.at<float>(v, u) = float(sum / 4.0);
      if (depth_m != nullptr) {
        // The camera-frame ray K⁻¹ (u, v, 1) has z = 1: its distance parameter is the depth.
        const double lambda =
            Trace(scene, centre, world_from_cam.linear() * (K_inverse * Eigen::Vector3d(u, v, 1.0))).first;
        if (std::isfinite(lambda)) depth_m->at<float>(v, u) = float(lambda);
      }
    }
  }
  grey.convertTo(view.image, CV_8UC1);
  return view;
}

Pose3d LookAt(const Eigen::Vector3d& centre_world, const Eigen::Vector3d& target_world) {
  const Eigen::Vector3d z = (target_world - centre_world).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.linear().col(0) = x;
  world_from_cam.linear().col(1) = z.cross(x);
  world_from_cam.linear().col(2) = z;
  world_from_cam.translation() = centre_world;
  return world_from_cam;
}

TexturedPlane Wall(double depth_m, std::uint64_t seed) {
  TexturedPlane p;
  p.texture = RandomTexture(1024, seed);
  p.texels_per_m = 60.0;
  p.axis_s = Eigen::Vector3d::UnitX();
  p.axis_t = Eigen::Vector3d::UnitY();
  p.point_world = Eigen::Vector3d(-0.5 * p.texture.cols / p.texels_per_m,
                                  -0.5 * p.texture.rows / p.texels_per_m, depth_m);
  return p;
}

TexturedPlane Ground(double height_m, std::uint64_t seed) {
  TexturedPlane ground;
  ground.texture = RandomTexture(2048, seed);
  ground.texels_per_m = 50.0;
  ground.axis_s = Eigen::Vector3d::UnitX();
  ground.axis_t = Eigen::Vector3d::UnitZ();
  ground.point_world = Eigen::Vector3d(-20.0, height_m, 0.5);
  return ground;
}

Pose3d PitchedDown() { return LookAt(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, std::tan(0.1745), 1.0)); }

}  // namespace semap::sweep_scene
