#include "engine/core/mesh.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

TEST(Mesh, Consistency) {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  EXPECT_TRUE(m.IsConsistent());
  m.labels = {1, 2};
  EXPECT_FALSE(m.IsConsistent());
  m.labels = {1, 2, 3};
  EXPECT_TRUE(m.IsConsistent());
  m.triangles.push_back({0, 1, 3});
  EXPECT_FALSE(m.IsConsistent());
}

}  // namespace
}  // namespace semap
