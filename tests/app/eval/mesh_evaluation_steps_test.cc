// The steps of EvaluateMesh (app/eval/mesh_evaluation_steps.h) on hand-made frames and depth maps, against
// figures the test works out itself.
#include "app/eval/mesh_evaluation_steps.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace semap::app {
namespace {

TEST(MeshEvaluationSteps, ErrorImagesGoToTheNamedFramesElseSpreadOverTheSelection) {
  io::SequenceInfo info;
  info.first_frame_id = 10;
  info.last_frame_id = 20;
  MeshEvaluationOptions o;
  EXPECT_TRUE(ErrorImageFrames(o, info).empty());
  o.error_images = 1;
  EXPECT_EQ(ErrorImageFrames(o, info), (std::set<std::int64_t>{15}));
  o.error_images = 3;
  EXPECT_EQ(ErrorImageFrames(o, info), (std::set<std::int64_t>{10, 15, 20}));
  o.error_images = 4;  // 10 + 10 k / 3, rounded
  EXPECT_EQ(ErrorImageFrames(o, info), (std::set<std::int64_t>{10, 13, 17, 20}));
  o.error_image_frames = {12, 3};
  EXPECT_EQ(ErrorImageFrames(o, info), (std::set<std::int64_t>{3, 12}));
}

TEST(MeshEvaluationSteps, TheClassSourceNamesEverySourceUsed) {
  EXPECT_EQ(ClassSourceText(false, false, false), "none");
  EXPECT_EQ(ClassSourceText(true, false, false), "label images");
  EXPECT_EQ(ClassSourceText(false, true, true), "segmenter labels and mesh labels");
  EXPECT_EQ(ClassSourceText(true, true, true), "label images and segmenter labels and mesh labels");
}

StereoCalibration Small() {
  StereoCalibration c;
  c.fx_px = c.fy_px = 50.0;
  c.cx_px = 20.0;
  c.cy_px = 15.0;
  c.baseline_m = 0.5;
  c.width_px = 40;
  c.height_px = 30;
  return c;
}

TEST(MeshEvaluationSteps, ExactDepthSamplesAreTheStridedPixelsInRangeInTheWorld) {
  const StereoCalibration c = Small();
  cv::Mat depth(9, 9, CV_32F);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = 2.0f + 0.5f * static_cast<float>(u + v);
  }
  depth.at<float>(4, 4) = 0.5f;  // nearer than min_depth_m
  DepthAccuracyOptions accuracy;
  accuracy.surface_pixel_stride = 3;  // pixels 1, 4, 7 in both directions
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  world_from_cam.translation() = Eigen::Vector3d(1.0, -2.0, 3.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> depths;
  SampleExactDepth(depth, c, world_from_cam, accuracy, &points, &depths);
  ASSERT_EQ(points.size(), 8u);  // 9 strided pixels, one too near
  ASSERT_EQ(depths.size(), 8u);
  size_t k = 0;
  for (int v = 1; v < depth.rows; v += 3) {
    for (int u = 1; u < depth.cols; u += 3) {
      if (u == 4 && v == 4) continue;
      const double z = 2.0 + 0.5 * (u + v);
      // The pinhole ray through the pixel at depth z, then the camera's pose.
      const Eigen::Vector3d cam((u - c.cx_px) * z / c.fx_px, (v - c.cy_px) * z / c.fy_px, z);
      const Eigen::Vector3d world = world_from_cam.linear() * cam + world_from_cam.translation();
      EXPECT_NEAR((points[k] - world).norm(), 0.0, 1e-12) << u << ", " << v;
      EXPECT_DOUBLE_EQ(depths[k], z);
      ++k;
    }
  }
}

// A mesh of the plane z = `depth_m` in front of the camera, wider than its view.
Mesh Wall(double depth_m) {
  Mesh m;
  m.vertices = {{-50, -50, depth_m}, {50, -50, depth_m}, {50, 50, depth_m}, {-50, 50, depth_m}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

Frame FrameAt(std::int64_t id, const Pose3d& world_from_cam) {
  Frame f;
  f.id = id;
  f.calibration = Small();
  f.left = cv::Mat(30, 40, CV_8UC3, cv::Scalar(90, 90, 90));
  f.world_from_cam = world_from_cam;
  return f;
}

TEST(MeshEvaluationSteps, TheEvaluatorSumsTheFramesScansAndCameras) {
  const Mesh wall = Wall(10.0);
  io::SequenceInfo info;  // no folder: no exact depth maps, no scene mesh
  const DepthAccuracyOptions accuracy;
  const MeshEvaluationOptions options;
  MeshEvaluator evaluator(wall, info, {}, accuracy, options);
  evaluator.AddUnreadable("first.bin: truncated");
  evaluator.AddUnreadable("second.bin: truncated");
  // Frame 0 at the origin sees three returns: two on the wall, one 2 m nearer (error +2 m).
  Frame a = FrameAt(0, Pose3d::Identity());
  a.velodyne = VelodyneScan{};
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(0, 0, 10), Eigen::Vector3f(1, 1, 10), Eigen::Vector3f(-1, 0, 8)}) {
    a.velodyne->points_velo.emplace_back(p.x(), p.y(), p.z(), 1.0f);
  }
  evaluator.AddFrame(a);
  // Frame 1, turned 90° about z (its −y is world +x), without a scan.
  Pose3d turned = Pose3d::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Frame b = FrameAt(1, turned);
  evaluator.AddFrame(b);
  const MeshEvaluation e = evaluator.Finish(ClassMap());
  EXPECT_EQ(e.frames, 2);
  EXPECT_EQ(e.frames_unreadable, 2);
  EXPECT_EQ(e.first_unreadable, "first.bin: truncated");
  EXPECT_EQ(e.frames_with_lidar, 1);
  EXPECT_EQ(e.frames_with_exact_depth, 0);
  EXPECT_EQ(e.lidar.reference_pixels, 3);
  EXPECT_EQ(e.lidar.compared_pixels, 3);
  EXPECT_NEAR(e.lidar.rmse_m, std::sqrt(4.0 / 3.0), 1e-5);  // errors 0, 0, +2 m
  EXPECT_NEAR(e.lidar.mean_error_m, 2.0 / 3.0, 1e-5);
  ASSERT_EQ(e.per_frame.size(), 2u);
  ASSERT_TRUE(e.per_frame[0].lidar.has_value());
  EXPECT_FALSE(e.per_frame[1].lidar.has_value());
  EXPECT_TRUE(e.lidar_breakdown.has_value());
  EXPECT_FALSE(e.lidar_static.has_value());  // no frame had labels
  EXPECT_EQ(e.class_source, "none");
  EXPECT_EQ(e.triangles, 2u);
  // The mean up: −y of (0, 1, 0) and of (−1, 0, 0): (1, −1, 0) / √2.
  EXPECT_NEAR((e.camera_up - Eigen::Vector3d(1, -1, 0) / std::sqrt(2.0)).norm(), 0.0, 1e-12);
  ASSERT_EQ(e.camera_centers.size(), 2u);
  EXPECT_EQ(e.camera_centers[1], Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace semap::app
