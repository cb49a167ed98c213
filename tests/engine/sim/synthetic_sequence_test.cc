#include "engine/sim/synthetic_sequence.h"

#include <gtest/gtest.h>

namespace semap::sim {
namespace {

SynthOptions Opts(ScenePreset preset, int frames) {
  SynthOptions o;
  o.preset = preset;
  o.num_frames = frames;
  o.seed = 1;
  return o;
}

TEST(SyntheticSequence, FramesAreDeterministicAndIndependentOfOrder) {
  const SyntheticSequence a(Opts(ScenePreset::kMixed, 4)), b(Opts(ScenePreset::kMixed, 4));
  const SyntheticFrame a3 = a.RenderFrame(3);
  (void)b.RenderFrame(1);  // another frame first: no hidden state
  const SyntheticFrame b3 = b.RenderFrame(3);
  EXPECT_EQ(cv::norm(a3.left.color, b3.left.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a3.right.color, b3.right.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a3.left.depth_m, b3.left.depth_m, cv::NORM_INF), 0.0);
  ASSERT_EQ(a3.scan.points_velo.size(), b3.scan.points_velo.size());
  for (size_t k = 0; k < a3.scan.points_velo.size(); k += 101)
    EXPECT_EQ(a3.scan.points_velo[k], b3.scan.points_velo[k]);
  EXPECT_NEAR(a3.timestamp_s, 0.3, 1e-12);
}

TEST(SyntheticSequence, SensorPosesFollowTheRig) {
  const SyntheticSequence s(Opts(ScenePreset::kUrban, 3));
  EXPECT_TRUE(s.world_from_scene().isApprox(s.scene_from_imu(0).inverse()));
  const Pose3d cam2 = s.scene_from_cam2(1), cam3 = s.scene_from_cam3(1);
  // The right camera sits baseline_m to the right (camera x) of the left one, same orientation.
  EXPECT_NEAR((cam2.inverse() * cam3.translation() - Eigen::Vector3d(0.54, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(cam2.linear().isApprox(cam3.linear()));
  // The left camera is about 1.65 m above the road, looking forward (scene z up).
  EXPECT_NEAR(cam2.translation().z(), 1.65, 0.02);
  EXPECT_GT(
      (cam2.linear() * Eigen::Vector3d::UnitZ()).dot(s.scene_from_imu(1).linear() * Eigen::Vector3d::UnitX()),
      0.99);
}

// Share of ground (road, sidewalk, terrain) and wall (building, wall, fence) pixels per preset.
TEST(SyntheticSequence, UrbanHasClearlyMoreGroundAndWallThanVegetated) {
  const ClassMap classes = ClassMap::Cityscapes();
  auto shares = [&](ScenePreset preset) {
    const SyntheticSequence s(Opts(preset, 30));
    LabelHistogram h;
    const CameraRenderer renderer(s.scene(), s.options());
    for (int i = 0; i < s.num_frames(); i += 6)
      h.Add(renderer.RenderGeometry(s.rig().calibration, s.scene_from_cam2(i)).labels);
    return h;
  };
  const LabelHistogram urban = shares(ScenePreset::kUrban), veg = shares(ScenePreset::kVegetated);
  const double urban_gw =
      urban.RoleShare(classes, ClassRole::kGround) + urban.RoleShare(classes, ClassRole::kWall);
  const double veg_gw = veg.RoleShare(classes, ClassRole::kGround) + veg.RoleShare(classes, ClassRole::kWall);
  EXPECT_GT(urban_gw, veg_gw + 0.15) << "urban " << urban_gw << " vegetated " << veg_gw;
  EXPECT_GT(veg.Share(label::kVegetation), 2.0 * urban.Share(label::kVegetation));
  EXPECT_GT(urban.RoleShare(classes, ClassRole::kWall), 2.0 * veg.RoleShare(classes, ClassRole::kWall));
}

TEST(LabelHistogram, CountsAndShares) {
  cv::Mat labels(2, 5, CV_8UC1, cv::Scalar(1));
  labels.at<std::uint8_t>(0, 0) = 3;
  labels.at<std::uint8_t>(1, 4) = 9;
  LabelHistogram h;
  h.Add(labels);
  EXPECT_EQ(h.total(), 10u);
  EXPECT_EQ(h.count(1), 8u);
  EXPECT_DOUBLE_EQ(h.Share(9), 0.1);
  const ClassMap c = ClassMap::Cityscapes();
  EXPECT_DOUBLE_EQ(h.RoleShare(c, ClassRole::kGround), 0.8);
  EXPECT_DOUBLE_EQ(h.RoleShare(c, ClassRole::kWall), 0.1);
  LabelHistogram g;
  g.Merge(h);
  g.Merge(h);
  EXPECT_EQ(g.count(3), 2u);
}

}  // namespace
}  // namespace semap::sim
