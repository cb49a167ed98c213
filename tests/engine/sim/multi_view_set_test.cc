#include "engine/sim/multi_view_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "engine/core/check.h"
#include "engine/sim/bvh.h"

namespace semap::sim {
namespace {

// The default layout at a quarter of the default image size (the same field of view).
MultiViewSetOptions SmallViews() {
  MultiViewSetOptions o;
  o.ScaleImage(0.25);
  return o;
}

SynthOptions Seed(std::uint64_t seed) {
  SynthOptions o;
  o.seed = seed;
  return o;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(MultiViewSet, ElevenCamerasOnAnArcAtFourToTenMetresLookAtTheObject) {
  const MultiViewSetOptions o;
  const MultiViewSet set(Seed(1), o);
  ASSERT_EQ(set.num_views(), 11);
  double previous_angle = -M_PI;
  for (int i = 0; i < set.num_views(); ++i) {
    SCOPED_TRACE("view " + std::to_string(i));
    const MultiViewCamera& c = set.camera(i);
    const Eigen::Matrix3d R = c.world_from_cam.linear();
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    const Eigen::Vector3d centre = c.world_from_cam.translation();
    const double distance = std::hypot(centre.x(), centre.y());
    EXPECT_GE(distance, o.min_distance_m);
    EXPECT_LE(distance, o.max_distance_m);
    EXPECT_LT(centre.y(), 0.0);  // in front of the object, the wall behind it
    // Along the arc, left to right; the optical axis through (near) the target, the image upright.
    const double angle = std::atan2(centre.x(), -centre.y());
    EXPECT_GT(angle, previous_angle);
    previous_angle = angle;
    EXPECT_LT(AngleDeg(R.col(2), set.target() - centre), 2.0);
    EXPECT_LT(R.col(1).z(), -0.9);
    EXPECT_NEAR(c.calibration.fx_px, c.K(0, 0), 0.0);
    EXPECT_NEAR(c.calibration.cy_px, c.K(1, 2), 0.0);
  }
  // Nearest at the arc's ends, farthest in its middle; the whole arc spans about arc_deg.
  const auto distance = [&](int i) { return set.camera(i).world_from_cam.translation().head<2>().norm(); };
  EXPECT_LT(distance(0), 5.0);
  EXPECT_LT(distance(10), 5.0);
  EXPECT_GT(distance(5), 9.0);
  const Eigen::Vector3d first = set.camera(0).world_from_cam.translation(),
                        last = set.camera(10).world_from_cam.translation();
  EXPECT_NEAR(AngleDeg({first.x(), first.y(), 0.0}, {last.x(), last.y(), 0.0}), o.arc_deg, 5.0);
}

TEST(MultiViewSet, EveryViewSeesTheGroundTheWallAndTheObject) {
  const MultiViewSet set(Seed(2), SmallViews());
  for (int i = 0; i < set.num_views(); ++i) {
    SCOPED_TRACE("view " + std::to_string(i));
    const CameraImage image = set.Render(i);
    ASSERT_EQ(image.color.size(), cv::Size(192, 128));
    std::map<int, int> pixels;
    int without_depth = 0;
    for (int y = 0; y < image.labels.rows; ++y) {
      for (int x = 0; x < image.labels.cols; ++x) {
        const int l = image.labels.at<std::uint8_t>(y, x);
        ++pixels[l];
        const float z = image.depth_m.at<float>(y, x);
        if (l != label::kSky) {
          EXPECT_GT(z, 0.5f);
          EXPECT_LT(z, 40.0f);
        }
        without_depth += z == 0.0f;
      }
    }
    const double total = image.labels.total();
    EXPECT_GT(pixels[label::kSidewalk] / total, 0.02);  // the nearest views see mostly the object
    EXPECT_GT(pixels[label::kBuilding] / total, 0.05);
    EXPECT_GT(pixels[kMultiViewObjectLabel] / total, 0.05);
    EXPECT_EQ(pixels[label::kSidewalk] + pixels[label::kBuilding] + pixels[kMultiViewObjectLabel] +
                  pixels[label::kSky],
              static_cast<int>(total));
    EXPECT_EQ(without_depth, pixels[label::kSky]);
  }
}

// The rasteriser's depth equals a ray cast through the pixel centres against the scene (its BVH).
TEST(MultiViewSet, DepthEqualsARayCastThroughThePixelCentres) {
  const MultiViewSet set(Seed(3), SmallViews());
  const TriangleBvh bvh(set.scene());
  for (const int view : {0, 5, 10}) {
    const MultiViewCamera& c = set.camera(view);
    const CameraImage image = set.Render(view);
    int checked = 0, agree = 0;
    for (int y = 1; y < image.depth_m.rows; y += 2) {
      for (int x = 1; x < image.depth_m.cols; x += 2) {
        const Eigen::Vector3d ray((x - c.K(0, 2)) / c.K(0, 0), (y - c.K(1, 2)) / c.K(1, 1), 1.0);
        const auto hit =
            bvh.Intersect(c.world_from_cam.translation(), c.world_from_cam.linear() * ray, 0.1, 1e6);
        if (!hit) continue;
        ++checked;
        agree += std::abs(image.depth_m.at<float>(y, x) - hit->t) <= 1e-4 * (1.0 + hit->t);
      }
    }
    ASSERT_GT(checked, 5000) << "view " << view;
    // Only pixels whose centre lies on an edge between two surfaces may differ.
    EXPECT_GT(agree, 0.995 * checked) << "view " << view;
  }
}

TEST(MultiViewSet, TheSameSeedGivesTheSameSetAnotherSeedAnotherOne) {
  const MultiViewSet a(Seed(4), SmallViews()), b(Seed(4), SmallViews()), c(Seed(5), SmallViews());
  EXPECT_EQ(a.scene().vertices, b.scene().vertices);
  EXPECT_NE(a.scene().vertices, c.scene().vertices);
  for (int i = 0; i < a.num_views(); ++i) {
    EXPECT_TRUE(a.camera(i).world_from_cam.isApprox(b.camera(i).world_from_cam, 0.0));
  }
  EXPECT_FALSE(a.camera(3).world_from_cam.isApprox(c.camera(3).world_from_cam, 1e-6));
  const CameraImage first = a.Render(3), again = b.Render(3);
  EXPECT_EQ(cv::norm(first.color, again.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(first.depth_m, again.depth_m, cv::NORM_INF), 0.0);
}

TEST(MultiViewSet, AScaledImageKeepsTheFieldOfView) {
  MultiViewSetOptions o;
  o.ScaleImage(0.25);
  EXPECT_EQ(o.image_width_px, 192);
  EXPECT_EQ(o.image_height_px, 128);
  EXPECT_DOUBLE_EQ(o.fx_px, 172.5);
  // The image's centre stays the centre: (768 - 1) / 2 = 383.5 becomes (192 - 1) / 2.
  EXPECT_DOUBLE_EQ(o.cx_px, 95.5);
  EXPECT_DOUBLE_EQ(o.cy_px, 63.5);
}

TEST(MultiViewSet, RefusesAnInvalidLayout) {
  MultiViewSetOptions o;
  o.num_views = 0;
  EXPECT_THROW(MultiViewSet(Seed(1), o), InvalidOption);
  o = MultiViewSetOptions();
  o.max_distance_m = 3.0;  // below min_distance_m
  EXPECT_THROW(MultiViewSet(Seed(1), o), InvalidOption);
}

}  // namespace
}  // namespace semap::sim
