#include "engine/depth/dominant_planes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace semap {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr double kFocalPx = 150.0;
constexpr double kCameraHeightM = 1.5;  // the ground is the plane y = 1.5 of the camera frame (y down)
constexpr double kWallDepthM = 8.0;     // the wall is the plane z = 8
constexpr Label kRoad = 1, kBuilding = 3, kCar = 14;  // Cityscapes: ground, wall, kept

// A camera at `centre` (world), its axes the world's: the ground below it, the wall ahead; each pixel's
// depth is the nearer of the two planes, labelled with it, with Gaussian noise and a car-labelled patch.
struct Scene {
  PlaneSweepView view;
  cv::Mat depth_m, labels;
};

Scene Render(const Eigen::Vector3d& centre, double noise_m, std::uint64_t seed) {
  Scene s;
  s.view.K << kFocalPx, 0.0, kWidth / 2.0, 0.0, kFocalPx, kHeight / 2.0, 0.0, 0.0, 1.0;
  s.view.world_from_cam = Pose3d::Identity();
  s.view.world_from_cam.translation() = centre;
  s.depth_m = cv::Mat::zeros(kHeight, kWidth, CV_32F);
  s.labels = cv::Mat::zeros(kHeight * 2, kWidth * 2, CV_8UC1);  // labels at twice the depth's size
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const double ray_y = (v - kHeight / 2.0) / kFocalPx;
      const double ground_z = ray_y > 0.0 ? kCameraHeightM / ray_y : INFINITY;
      const bool ground = ground_z < kWallDepthM;
      const bool car = u > 100 && u < 120 && v > 50 && v < 70;
      s.depth_m.at<float>(v, u) = static_cast<float>((ground ? ground_z : kWallDepthM) + noise(rng));
      const Label l = car ? kCar : ground ? kRoad : kBuilding;
      s.labels(cv::Rect(2 * u, 2 * v, 2, 2)).setTo(l);
    }
  }
  return s;
}

// The world plane nᵀX = c of a direction's middle offset, with n turned to have a positive `axis` entry.
std::pair<Eigen::Vector3d, double> MiddlePlane(const SweepDirection& d, int axis) {
  const double sign = d.normal_world[axis] < 0.0 ? -1.0 : 1.0;
  return {sign * d.normal_world, sign * 0.5 * (d.min_offset_m + d.max_offset_m)};
}

TEST(DominantDirections, TheGroundAndTheWallFromTheirLabels) {
  const Eigen::Vector3d centre(2.0, -1.0, 3.0);
  const Scene s = Render(centre, 0.02, 1);
  const std::vector<SweepDirection> d =
      DominantDirections(s.depth_m, s.labels, s.view, ClassMap::Cityscapes());
  ASSERT_EQ(d.size(), 2u);
  // Ground first: world y = centre.y + 1.5; the wall: world z = centre.z + 8.
  const auto [ground_n, ground_c] = MiddlePlane(d[0], 1);
  EXPECT_NEAR(ground_n.y(), 1.0, 1e-3);
  EXPECT_NEAR(ground_c, centre.y() + kCameraHeightM, 0.02);
  const auto [wall_n, wall_c] = MiddlePlane(d[1], 2);
  EXPECT_NEAR(wall_n.z(), 1.0, 1e-3);
  EXPECT_NEAR(wall_c, centre.z() + kWallDepthM, 0.02);
  // The offsets: ± 20 % of each plane's distance from the camera, the camera outside them.
  EXPECT_NEAR(d[0].max_offset_m - d[0].min_offset_m, 2.0 * 0.2 * kCameraHeightM, 0.02);
  EXPECT_NEAR(d[1].max_offset_m - d[1].min_offset_m, 2.0 * 0.2 * kWallDepthM, 0.05);
  for (const SweepDirection& x : d) {
    const double along = x.normal_world.dot(centre);
    EXPECT_TRUE(along < x.min_offset_m || along > x.max_offset_m);
  }
  // The same input, the same directions.
  const std::vector<SweepDirection> again =
      DominantDirections(s.depth_m, s.labels, s.view, ClassMap::Cityscapes());
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0].min_offset_m, d[0].min_offset_m);
}

TEST(DominantDirections, NoneWithoutEnoughPointsOrLabels) {
  const Scene s = Render(Eigen::Vector3d::Zero(), 0.02, 2);
  DominantPlaneOptions o;
  o.min_points = kWidth * kHeight;  // more than either role has
  EXPECT_TRUE(DominantDirections(s.depth_m, s.labels, s.view, ClassMap::Cityscapes(), o).empty());
  EXPECT_TRUE(DominantDirections(s.depth_m, cv::Mat(), s.view, ClassMap::Cityscapes()).empty());
  // Depth too noisy for any plane to explain half of a role's points.
  const Scene noisy = Render(Eigen::Vector3d::Zero(), 3.0, 3);
  EXPECT_TRUE(DominantDirections(noisy.depth_m, noisy.labels, noisy.view, ClassMap::Cityscapes()).empty());
}

}  // namespace
}  // namespace semap
