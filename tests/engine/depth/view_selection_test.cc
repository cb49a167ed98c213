#include "engine/depth/view_selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/engine/depth/sweep_scene.h"

namespace semap {
namespace {

// A camera at `centre` whose optical axis (z) points along `axis`, y roughly down (world +y).
Pose3d Looking(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis) {
  return sweep_scene::LookAt(centre, centre + axis);
}

// Cameras on an arc of radius 6 m around the origin, each looking at it, `step_deg` apart.
std::vector<Pose3d> Arc(int count, double step_deg) {
  std::vector<Pose3d> poses;
  for (int i = 0; i < count; ++i) {
    const double a = (i - count / 2) * step_deg * M_PI / 180.0;
    const Eigen::Vector3d centre(6.0 * std::sin(a), 0.0, -6.0 * std::cos(a));
    poses.push_back(Looking(centre, -centre));
  }
  return poses;
}

TEST(SelectNeighbourViews, NearestCamerasOnAnArcFirst) {
  const std::vector<Pose3d> arc = Arc(11, 8.0);
  ViewSelectionOptions o;
  o.max_views = 4;
  // The middle camera (index 5): its two neighbours on each side, the nearer pair first (equal distances:
  // the lower index first).
  EXPECT_EQ(SelectNeighbourViews(arc[5], arc, o), (std::vector<std::size_t>{4, 6, 3, 7}));
  // The first camera has neighbours on one side only.
  EXPECT_EQ(SelectNeighbourViews(arc[0], arc, o), (std::vector<std::size_t>{1, 2, 3, 4}));
}

TEST(SelectNeighbourViews, SkipsTheReferenceItselfCamerasLookingElsewhereAndKeepsTheLimit) {
  std::vector<Pose3d> candidates = Arc(3, 10.0);
  const Pose3d reference = candidates[1];
  // Beside the reference but facing the other way, and one at the reference's own place.
  candidates.push_back(
      Looking(reference.translation() + Eigen::Vector3d(0.1, 0.0, 0.0), -reference.linear().col(2)));
  candidates.push_back(reference);
  ViewSelectionOptions o;
  o.max_views = 10;
  EXPECT_EQ(SelectNeighbourViews(reference, candidates, o), (std::vector<std::size_t>{0, 2}));
  o.max_views = 1;
  EXPECT_EQ(SelectNeighbourViews(reference, candidates, o).size(), 1u);
  // Turned 50°: within the default 60° of the reference's axis; at 70° it is not.
  const double turn = 50.0 * M_PI / 180.0;
  const Eigen::Vector3d axis = reference.linear().col(2);
  const Eigen::Vector3d side = reference.linear().col(0);
  const std::vector<Pose3d> turned{
      Looking(reference.translation() + side, std::cos(turn) * axis + std::sin(turn) * side),
      Looking(reference.translation() + side, std::cos(1.4 * turn) * axis + std::sin(1.4 * turn) * side)};
  EXPECT_EQ(SelectNeighbourViews(reference, turned, ViewSelectionOptions()), (std::vector<std::size_t>{0}));
}

}  // namespace
}  // namespace semap
