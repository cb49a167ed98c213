#include "io/lcm/lcm_codec.h"

#include <gtest/gtest.h>

namespace semap::io {
namespace {

TEST(LcmCodec, DeltaRoundTripsThroughEncodeDecode) {
  MeshDelta d;
  d.frame_id = 7;
  d.removed_triangle_ids = {3, 9};
  d.vertex_ids = {10, 11, 12};
  d.vertex_positions = {{0.5, 1, 2}, {3, 4, 5}, {6, 7, 8.25}};
  d.vertex_colors_rgb = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}};
  d.vertex_labels = {1, 3, 14};
  d.added_triangle_ids = {20};
  d.added_triangles = {{10, 11, 12}};
  const auto msg = ToLcmDelta(d, 5, 123);
  std::vector<std::uint8_t> buffer(msg.getEncodedSize());
  ASSERT_EQ(msg.encode(buffer.data(), 0, static_cast<int>(buffer.size())), static_cast<int>(buffer.size()));
  semap_lcm::mesh_delta_t decoded;
  ASSERT_GT(decoded.decode(buffer.data(), 0, static_cast<int>(buffer.size())), 0);
  EXPECT_EQ(decoded.sequence, 5);
  const MeshDelta back = FromLcm(decoded);
  EXPECT_EQ(back.frame_id, 7);
  EXPECT_EQ(back.removed_triangle_ids, d.removed_triangle_ids);
  EXPECT_EQ(back.vertex_ids, d.vertex_ids);
  EXPECT_EQ(back.vertex_positions, d.vertex_positions);  // exactly representable in float
  EXPECT_EQ(back.vertex_colors_rgb, d.vertex_colors_rgb);
  EXPECT_EQ(back.vertex_labels, d.vertex_labels);
  EXPECT_EQ(back.added_triangles, d.added_triangles);
}

TEST(LcmCodec, InconsistentMessageIsRejected) {
  semap_lcm::mesh_delta_t msg{};
  msg.num_vertices = 2;  // but no arrays
  EXPECT_THROW(FromLcm(msg), std::runtime_error);
}

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
