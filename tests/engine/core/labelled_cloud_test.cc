#include "engine/core/labelled_cloud.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

LabelledCloud ThreePoints() {
  LabelledCloud c;
  c.positions_world = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  c.labels = {1, 3, 9};
  c.camera_index = {0, 0, 1};
  c.camera_centers_world = {{0, 0, -1}, {1, 0, -1}};
  c.camera_frame_ids = {10, 11};
  return c;
}

TEST(LabelledCloud, SubsetCarriesEveryAttribute) {
  const auto c = ThreePoints();
  const auto s = c.Subset({2, 0});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.positions_world[0], Eigen::Vector3d(2, 0, 0));
  EXPECT_EQ(s.labels, (std::vector<Label>{9, 1}));
  EXPECT_EQ(s.camera_index, (std::vector<std::uint32_t>{1, 0}));
  EXPECT_TRUE(s.colors_rgb.empty());
  EXPECT_EQ(s.camera_centers_world.size(), 2u);
  s.AssertConsistent();
}

TEST(LabelledCloud, AppendOffsetsCamerasAndFillsMissingAttributes) {
  auto a = ThreePoints();
  LabelledCloud b;
  b.positions_world = {{5, 5, 5}};
  b.colors_rgb = {{{1, 2, 3}}};
  b.camera_index = {0};
  b.camera_centers_world = {{9, 9, 9}};
  b.camera_frame_ids = {12};
  a.Append(b);
  a.AssertConsistent();
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a.camera_index[3], 2u);
  EXPECT_EQ(a.camera_centers_world[2], Eigen::Vector3d(9, 9, 9));
  ASSERT_EQ(a.colors_rgb.size(), 4u);
  EXPECT_EQ(a.colors_rgb[3], (std::array<std::uint8_t, 3>{1, 2, 3}));
  ASSERT_EQ(a.labels.size(), 4u);
  EXPECT_EQ(a.labels[3], 0);  // b had no labels: filled with the default id
}

}  // namespace
}  // namespace semap
