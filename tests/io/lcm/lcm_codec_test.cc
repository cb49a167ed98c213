#include "io/lcm/lcm_codec.h"

#include <gtest/gtest.h>

namespace semap::io {
namespace {

TEST(LcmCodec, PoseIsCentreAndUnitQuaternion) {
  Pose3d p = Pose3d::Identity();
  p.translate(Eigen::Vector3d(1, 2, 3));
  p.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()));
  const auto m = ToLcmPose(4, 0.4, p, 1);
  EXPECT_DOUBLE_EQ(m.position[1], 2.0);
  const Eigen::Quaterniond q(m.orientation[0], m.orientation[1], m.orientation[2], m.orientation[3]);
  EXPECT_NEAR(q.angularDistance(Eigen::Quaterniond(p.rotation())), 0.0, 1e-12);
}

}  // namespace
}  // namespace semap::io
