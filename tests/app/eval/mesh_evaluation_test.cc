#include "app/eval/mesh_evaluation.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "engine/core/check.h"
#include "io/kitti/ground_truth.h"
#include "tests/common/test_data.h"

namespace semap::app {
namespace {

using namespace io;  // the datasets, ground truth and mesh files the evaluation reads

// A mesh of the surface seen in a disparity map: pixels (x, y), (x+1, y), (x, y+1), (x+1, y+1) with valid
// disparities within 5 % of each other give two triangles. `keep_columns_below` cuts the mesh at a column.
Mesh MeshFromDisparity(const cv::Mat& disparity, const StereoCalibration& cal, int keep_columns_below) {
  Mesh m;
  cv::Mat index(disparity.size(), CV_32S, cv::Scalar(-1));
  auto vertex = [&](int x, int y) {
    int& i = index.at<int>(y, x);
    if (i < 0) {
      i = static_cast<int>(m.vertices.size());
      m.vertices.push_back(cal.Unproject(x, y, cal.DepthFromDisparity(disparity.at<float>(y, x))));
    }
    return static_cast<std::uint32_t>(i);
  };
  for (int y = 0; y + 1 < disparity.rows; ++y) {
    for (int x = 0; x + 1 < std::min(disparity.cols, keep_columns_below); ++x) {
      const float d[4] = {disparity.at<float>(y, x), disparity.at<float>(y, x + 1),
                          disparity.at<float>(y + 1, x), disparity.at<float>(y + 1, x + 1)};
      const float lo = *std::min_element(d, d + 4), hi = *std::max_element(d, d + 4);
      if (lo <= 0.0f || hi > 1.05f * lo) continue;
      const auto a = vertex(x, y), b = vertex(x + 1, y), c = vertex(x, y + 1), e = vertex(x + 1, y + 1);
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, e});
    }
  }
  return m;
}

TEST(EvaluateMesh, GroundTruthDisparityMeshAgreesWithVelodyneAndHolesLowerCompleteness) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  const auto dataset = test::SharedDir() / "data/kitti_stereo2015_subset";
  FrameSourceOptions input;
  input.max_frames = 1;
  const SequenceInfo info = DescribeDataset(dataset, input);
  char name[32];
  std::snprintf(name, sizeof(name), "%06lld_10.png", static_cast<long long>(info.first_frame_id));
  const cv::Mat disparity = ReadKittiDisparityPng(dataset / "disp_occ_0" / name);
  const Mesh full = MeshFromDisparity(disparity, info.calibration, disparity.cols);
  ASSERT_GT(full.num_triangles(), 10000u);

  const auto e = EvaluateMesh(full, dataset, input);
  EXPECT_EQ(e.frames, 1);
  EXPECT_EQ(e.frames_with_lidar, 1);
  EXPECT_FALSE(e.exact_depth.has_value());
  // Its one camera at the identity pose (stereo-2015 has no poses): a camera frame's up is −y.
  ASSERT_EQ(e.camera_centers.size(), 1u);
  EXPECT_EQ(e.camera_centers[0], Eigen::Vector3d::Zero());
  EXPECT_EQ(e.camera_up, Eigen::Vector3d(0, -1, 0));
  EXPECT_FALSE(e.scene.has_value());
  std::printf("GT-disparity mesh vs Velodyne: RMSE %.3f m, median %.3f m, completeness %.3f (%lld px)\n",
              e.lidar.rmse_m, e.lidar.median_abs_m, e.lidar.completeness,
              static_cast<long long>(e.lidar.reference_pixels));
  // Every pixel centre of the grid is a mesh vertex: where the mesh covers a pixel, its rendered depth is the
  // GT depth of that pixel (an independent check of the renderer on a real 100k-triangle mesh).
  const cv::Mat rendered = RenderDepth(full, info.calibration, Pose3d::Identity());
  int covered = 0;
  for (int y = 0; y < rendered.rows; ++y) {
    for (int x = 0; x < rendered.cols; ++x) {
      const float z = rendered.at<float>(y, x);
      if (z <= 0.0f) continue;
      ++covered;
      ASSERT_GT(disparity.at<float>(y, x), 0.0f) << x << "," << y;
      const double z_gt = info.calibration.DepthFromDisparity(disparity.at<float>(y, x));
      ASSERT_NEAR(z, z_gt, 1e-4 * z_gt) << x << "," << y;
    }
  }
  EXPECT_GT(covered, 10000);
  // The GT disparity agrees with the projected Velodyne to 0.63 px on average (shared/README), centimetres to
  // decimetres of depth: the median error is small. (disp_occ_0 is semi-dense and the grid mesh needs four
  // valid neighbours, so completeness is low; RMSE is dominated by LiDAR points across depth edges.)
  EXPECT_LT(e.lidar.median_abs_m, 0.15);
  EXPECT_GT(e.lidar.rmse_m, e.lidar.median_abs_m);
  EXPECT_GT(e.lidar.completeness, 0.05);
  EXPECT_GT(e.lidar.reference_pixels, 5000);

  // Half the mesh: completeness drops, the error of what is left does not grow.
  const Mesh half = MeshFromDisparity(disparity, info.calibration, disparity.cols / 2);
  const auto h = EvaluateMesh(half, dataset, input);
  EXPECT_LT(h.lidar.completeness, 0.75 * e.lidar.completeness);
  EXPECT_EQ(h.lidar.reference_pixels, e.lidar.reference_pixels);
  EXPECT_LT(h.triangles, e.triangles);
  EXPECT_LT(h.off_bytes, e.off_bytes);
}

TEST(EvaluateMesh, BothProtocolsTheBreakdownAndAnErrorImageOfTheAskedFrame) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  const auto dataset = test::SharedDir() / "data/kitti_stereo2015_subset";
  FrameSourceOptions input;
  input.max_frames = 1;
  const SequenceInfo info = DescribeDataset(dataset, input);
  char name[32];
  std::snprintf(name, sizeof(name), "%06lld_10.png", static_cast<long long>(info.first_frame_id));
  const Mesh mesh = MeshFromDisparity(ReadKittiDisparityPng(dataset / "disp_occ_0" / name), info.calibration,
                                      std::numeric_limits<int>::max());
  MeshEvaluationOptions options;
  options.error_images = 1;
  const auto e = EvaluateMesh(mesh, dataset, input, DepthAccuracyOptions(), options);
  // The paper protocol: a subset of the reference pixels (<= 15 m), errors beyond 2 m left out.
  EXPECT_DOUBLE_EQ(e.paper_options.max_depth_m, 15.0);
  EXPECT_LT(e.lidar_paper.reference_pixels, e.lidar.reference_pixels);
  EXPECT_LE(e.lidar_paper.rmse_m, e.lidar.rmse_m);
  EXPECT_EQ(e.lidar.excluded_pixels, 0);
  // The breakdown covers the strict figures' pixels; the grid mesh has no labels and the subset's frames no
  // label images: every pixel is "no class".
  ASSERT_TRUE(e.lidar_breakdown.has_value());
  EXPECT_FALSE(e.exact_depth_breakdown.has_value());
  EXPECT_EQ(e.class_source, "none");
  ASSERT_EQ(e.lidar_breakdown->by_class.size(), 1u);
  EXPECT_EQ(e.lidar_breakdown->by_class[0].name, "no class");
  EXPECT_EQ(e.lidar_breakdown->by_class[0].reference_pixels, e.lidar.reference_pixels);
  std::int64_t compared = 0;
  for (const ErrorBin& b : e.lidar_breakdown->by_distance) compared += b.compared_pixels;
  EXPECT_EQ(compared, e.lidar.compared_pixels);
  compared = 0;
  for (const ErrorBin& b : e.lidar_breakdown->by_triangle_area) compared += b.compared_pixels;
  EXPECT_EQ(compared, e.lidar.compared_pixels);
  // One error image, of the only frame, with its legend band under the image.
  ASSERT_EQ(e.error_images.size(), 1u);
  EXPECT_EQ(e.error_images[0].frame_id, info.first_frame_id);
  EXPECT_EQ(e.error_images[0].reference, "lidar");
  EXPECT_EQ(e.error_images[0].image.cols, info.calibration.width_px);
  EXPECT_GT(e.error_images[0].image.rows, info.calibration.height_px);
  // Bad options are named.
  options.error_images = -1;
  EXPECT_THROW(EvaluateMesh(mesh, dataset, input, DepthAccuracyOptions(), options), InvalidOption);
}

TEST(EvaluateMesh, MissingDatasetIsAClearError) {
  try {
    EvaluateMesh(Mesh{}, "/no/such/dataset", FrameSourceOptions{});
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/dataset"), std::string::npos);
  }
}

}  // namespace
}  // namespace semap::app
