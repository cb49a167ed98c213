#include "engine/core/class_map.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

TEST(ClassMap, CityscapesTargetsAreThePapersGroundAndWalls) {
  const auto m = ClassMap::Cityscapes();
  EXPECT_EQ(m.classes().size(), 20u);
  EXPECT_EQ(m.unlabelled_id(), 0);
  for (const char* ground : {"Road", "Sidewalk", "Terrain"}) {
    EXPECT_EQ(m.Role(static_cast<Label>(m.FindByName(ground))), ClassRole::kGround) << ground;
  }
  for (const char* wall : {"Building", "Wall", "Fence"}) {
    EXPECT_EQ(m.Role(static_cast<Label>(m.FindByName(wall))), ClassRole::kWall) << wall;
  }
  for (const char* keep : {"Vegetation", "Car", "Pole", "Unlabeled", "Sky"}) {
    EXPECT_FALSE(m.IsTarget(static_cast<Label>(m.FindByName(keep)))) << keep;
  }
}

TEST(ClassMap, LookupAndUnknownIds) {
  const auto m = ClassMap::Cityscapes();
  EXPECT_EQ(m.FindByName("vegetation"), 9);
  EXPECT_EQ(m.FindByName("no such class"), -1);
  EXPECT_FALSE(m.Contains(200));
  EXPECT_EQ(m.Role(200), ClassRole::kKeep);
  EXPECT_EQ(m.Color(200), (std::array<std::uint8_t, 3>{0, 0, 0}));
  EXPECT_EQ(m.Color(14), (std::array<std::uint8_t, 3>{0, 0, 142}));
  EXPECT_EQ(m.Get(14).name, "Car");
}

}  // namespace
}  // namespace semap
