#include "engine/depth/frame_sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "tests/engine/depth/sweep_scene.h"

namespace semap {
namespace {

using namespace sweep_scene;

constexpr double kWallDepthM = 5.07;
constexpr double kBaselineM = 0.4;

// A frame of the reference view (colour, as a multi-view set's frame is) with four neighbour views of a
// fronto-parallel wall, its exact depth in `truth_m`.
Frame WallFrame(cv::Mat* truth_m) {
  const std::vector<TexturedPlane> scene{Wall(kWallDepthM, 1)};
  const PlaneSweepView reference = Render(scene, Pose3d::Identity(), truth_m);
  Frame f;
  f.id = 7;
  cv::cvtColor(reference.image, f.left, cv::COLOR_GRAY2BGR);
  f.calibration.fx_px = reference.K(0, 0);
  f.calibration.fy_px = reference.K(1, 1);
  f.calibration.cx_px = reference.K(0, 2);
  f.calibration.cy_px = reference.K(1, 2);
  f.calibration.width_px = kWidth;
  f.calibration.height_px = kHeight;
  f.calibration.baseline_m = kBaselineM;
  f.world_from_cam = Pose3d::Identity();
  const Eigen::Vector3d target(0.0, 0.0, kWallDepthM);
  std::int64_t id = 0;
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(-kBaselineM, 0.0, 0.0), Eigen::Vector3d(kBaselineM, 0.05, 0.1),
        Eigen::Vector3d(0.0, -0.5, -0.2), Eigen::Vector3d(0.1, 0.5, 0.0)}) {
    CalibratedView n = Render(scene, LookAt(c, target));
    n.frame_id = id++;
    f.neighbour_views.push_back(n);
  }
  return f;
}

PlaneSweepOptions WallSweep() {
  PlaneSweepOptions o;
  o.num_planes = 64;
  o.min_depth_m = 2.0;
  o.max_depth_m = 20.0;
  return o;
}

// The share of valid pixels, and of those, the share whose depth f·B / d lies within `tolerance_m` of the
// truth.
std::pair<double, double> Score(const DisparityResult& r, const Frame& f, const cv::Mat& truth_m,
                                double tolerance_m) {
  int with_truth = 0, valid = 0, accurate = 0;
  for (int v = 0; v < truth_m.rows; ++v) {
    for (int u = 0; u < truth_m.cols; ++u) {
      if (!(truth_m.at<float>(v, u) > 0.0f)) continue;
      ++with_truth;
      const float d = r.disparity_px.at<float>(v, u);
      if (!(d > 0.0f)) {
        EXPECT_EQ(r.confidence.at<float>(v, u), 0.0f);
        continue;
      }
      EXPECT_EQ(r.confidence.at<float>(v, u), 1.0f);
      ++valid;
      const double z = f.calibration.fx_px * f.calibration.baseline_m / d;
      if (std::abs(z - truth_m.at<float>(v, u)) <= tolerance_m) ++accurate;
    }
  }
  return {double(valid) / std::max(with_truth, 1), double(accurate) / std::max(valid, 1)};
}

// The plane step at the wall's depth: z² (1/min − 1/max) / (planes − 1) ≈ 0.16 m.
const double kStepM = kWallDepthM * kWallDepthM * (1.0 / 2.0 - 1.0 / 20.0) / 63.0;

struct SweepCase {
  bool half_resolution;
  double tolerance_steps;  // accurate: within this many plane steps of the truth
  double min_valid_share, min_accurate_share;
};

class SweepFrameDisparityAt : public testing::TestWithParam<SweepCase> {};

// Full resolution, and half (brought back at full size, at twice the tolerance).
TEST_P(SweepFrameDisparityAt, IsTheDisparityOfTheFramesBaselineAtTheSweptDepth) {
  const SweepCase c = GetParam();
  cv::Mat truth_m;
  const Frame f = WallFrame(&truth_m);
  const DisparityResult r = SweepFrameDisparity(f, PlaneSweepDepth(WallSweep()), c.half_resolution);
  ASSERT_EQ(r.disparity_px.size(), f.left.size());
  ASSERT_EQ(r.disparity_px.type(), CV_32F);
  const auto [valid_share, accurate_share] = Score(r, f, truth_m, c.tolerance_steps * kStepM);
  EXPECT_GE(valid_share, c.min_valid_share);
  EXPECT_GE(accurate_share, c.min_accurate_share);
}

INSTANTIATE_TEST_SUITE_P(Resolutions, SweepFrameDisparityAt,
                         testing::Values(SweepCase{false, 0.25, 0.9, 0.95}, SweepCase{true, 0.5, 0.85, 0.9}));

TEST(SweepFrameDisparity, ScaledViewsKeepThePixelCentres) {
  // A world point's pixel in the half-size view is where the full-size pixel's centre lands: (u + ½)/2 − ½.
  cv::Mat truth_m;
  const Frame f = WallFrame(&truth_m);
  const PlaneSweepView full = ReferenceView(f, 1.0), half = ReferenceView(f, 0.5);
  EXPECT_EQ(half.image.size(), cv::Size(kWidth / 2, kHeight / 2));
  EXPECT_EQ(half.image.type(), CV_8UC1);
  const Eigen::Vector3d x(0.3, -0.2, 4.0);
  const Eigen::Vector3d p_full = full.K * x, p_half = half.K * x;
  EXPECT_NEAR(p_half.x() / p_half.z(), (p_full.x() / p_full.z() + 0.5) / 2.0 - 0.5, 1e-9);
  EXPECT_NEAR(p_half.y() / p_half.z(), (p_full.y() / p_full.z() + 0.5) / 2.0 - 0.5, 1e-9);
  const PlaneSweepView n = ScaledView(f.neighbour_views[0], 0.5);
  EXPECT_EQ(n.frame_id, f.neighbour_views[0].frame_id);
  EXPECT_EQ(n.image.size(), cv::Size(kWidth / 2, kHeight / 2));
}

TEST(SweepFrameDisparity, RefusesFramesItCannotSweepNamingTheFrame) {
  cv::Mat truth_m;
  const Frame good = WallFrame(&truth_m);
  const PlaneSweepDepth sweep(WallSweep());
  auto expect_error = [&](Frame f, const std::string& words) {
    try {
      SweepFrameDisparity(f, sweep, false);
      ADD_FAILURE() << "accepted a frame without " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("frame 7"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  Frame no_neighbours = good;
  no_neighbours.neighbour_views.clear();
  expect_error(no_neighbours, "no neighbour views");
  Frame no_pose = good;
  no_pose.world_from_cam.reset();
  expect_error(no_pose, "pose");
  Frame no_baseline = good;
  no_baseline.calibration.baseline_m = 0.0;
  expect_error(no_baseline, "baseline");
}

}  // namespace
}  // namespace semap
