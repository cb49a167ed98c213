// The Strecha reader on the real fountain-P11 set in ../shared (halved to 1536 × 1024).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "io/sfm/strecha.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

constexpr const char* kFountain = "data/strecha_fountain_p11";
// The original 3072 × 2048 images' focal length, px; the halved set's K is half of it.
constexpr double kOriginalFocalPx = 2759.48;

TEST(StrechaFountain, ReadsAllElevenViews) {
  SEMAP_REQUIRE_SHARED(kFountain);
  const std::vector<StrechaView> views = ReadStrechaSet(test::SharedDir() / kFountain);
  ASSERT_EQ(views.size(), 11u);
  // The point nearest to every optical axis: the fountain, in front of every camera.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < views.size(); ++i) {
    const StrechaView& v = views[i];
    SCOPED_TRACE(v.image.string());
    EXPECT_EQ(v.image.filename().string(), (i < 10 ? "000" : "00") + std::to_string(i) + ".jpg");
    EXPECT_EQ(v.width_px, 1536);
    EXPECT_EQ(v.height_px, 1024);
    EXPECT_NEAR(v.K(0, 0), kOriginalFocalPx / 2.0, 1.0);
    EXPECT_NEAR(v.K(1, 1), kOriginalFocalPx / 2.0, 3.0);
    EXPECT_NEAR(v.K(0, 2), 1536 / 2.0, 20.0);
    EXPECT_NEAR(v.K(1, 2), 1024 / 2.0, 20.0);
    EXPECT_NEAR(v.world_from_cam.linear().determinant(), 1.0, 1e-3);
    if (i > 0) {
      const double step_m =
          (v.world_from_cam.translation() - views[i - 1].world_from_cam.translation()).norm();
      EXPECT_GT(step_m, 0.2);
      EXPECT_LT(step_m, 3.0);
    }
    const Eigen::Vector3d axis = v.world_from_cam.linear().col(2);
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - axis * axis.transpose();
    A += P;
    b += P * v.world_from_cam.translation();
  }
  const Eigen::Vector3d fountain = A.ldlt().solve(b);
  for (const StrechaView& v : views) {
    const double depth_m = (v.world_from_cam.inverse(Eigen::Isometry) * fountain).z();
    EXPECT_GT(depth_m, 3.0) << v.image;
    EXPECT_LT(depth_m, 20.0) << v.image;
  }
}

}  // namespace
}  // namespace semap::io
