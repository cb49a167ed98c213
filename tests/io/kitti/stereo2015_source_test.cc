// The stereo-2015 reader on the real subset in ../shared: 20 frames, and the calibration checked against
// the ground truth: Velodyne points projected into cam 2 land on the GT disparity.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "io/frame_source.h"
#include "io/kitti/ground_truth.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// Points closer than this are on the vehicle or too near to be seen by both cameras.
constexpr double kMinDepthM = 2.0;

TEST(KittiStereo2015Source, RealSubsetVelodyneMatchesGroundTruthDisparity) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  const fs::path root = test::SharedDir() / "data/kitti_stereo2015_subset";
  ASSERT_EQ(DetectLayout(root), DatasetLayout::kKittiStereo2015);
  auto source = OpenFrameSource(root, {});
  ASSERT_EQ(source->size(), 20);
  double sum_abs_px = 0.0;
  std::int64_t matched = 0;
  std::int64_t frames = 0;
  std::int64_t previous_id = -1;
  while (auto f = source->Next()) {
    ++frames;
    EXPECT_GT(f->id, previous_id);
    previous_id = f->id;
    EXPECT_EQ(f->left.type(), CV_8UC3);
    EXPECT_EQ(f->calibration.width_px, 1242);
    EXPECT_EQ(f->calibration.height_px, 375);
    EXPECT_NEAR(f->calibration.baseline_m, 0.5327, 1e-4);
    ASSERT_TRUE(f->world_from_cam);
    EXPECT_TRUE(f->world_from_cam->isApprox(Pose3d::Identity()));
    ASSERT_TRUE(f->velodyne);
    EXPECT_GT(f->velodyne->points_velo.size(), 50000u);
    char name[32];
    std::snprintf(name, sizeof(name), "%06lld_10.png", static_cast<long long>(f->id));
    const cv::Mat gt = ReadKittiDisparityPng(root / "disp_occ_0" / name);
    ASSERT_EQ(gt.size(), f->left.size());
    double frame_sum = 0.0;
    std::int64_t frame_n = 0;
    for (const auto& pv : f->velodyne->points_velo) {
      const Eigen::Vector3d p = f->velodyne->cam_from_velo * pv.head<3>().cast<double>();
      if (p.z() < kMinDepthM) continue;
      const Eigen::Vector2d uv = f->calibration.Project(p);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= gt.cols || v >= gt.rows) continue;
      const float d_gt = gt.at<float>(v, u);
      if (d_gt <= 0.f) continue;
      frame_sum += std::abs(f->calibration.DisparityFromDepth(p.z()) - d_gt);
      ++frame_n;
    }
    ASSERT_GT(frame_n, 1000) << "frame " << f->id;
    sum_abs_px += frame_sum;
    matched += frame_n;
  }
  EXPECT_EQ(frames, 20);
  const double mean_px = sum_abs_px / static_cast<double>(matched);
  std::printf("[ figure ] Velodyne vs GT disparity over %lld frames: %lld points, mean |error| = %.3f px\n",
              static_cast<long long>(frames), static_cast<long long>(matched), mean_px);
  EXPECT_LT(mean_px, 1.0);
}

TEST(KittiStereo2015Source, ReadsWithoutVelodyneOnRequest) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  FrameSourceOptions o;
  o.load_velodyne = false;
  o.first_frame = 100;
  auto source = OpenFrameSource(test::SharedDir() / "data/kitti_stereo2015_subset", o);
  ASSERT_EQ(source->size(), 5);  // 110, 117, 123, 130, 144
  const auto f = source->Next();
  ASSERT_TRUE(f);
  EXPECT_EQ(f->id, 110);
  EXPECT_FALSE(f->velodyne);
}

}  // namespace
}  // namespace semap::io
