#include "engine/depth/stereo_sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

namespace semap {
namespace {

constexpr double kFocalPx = 700.0;
constexpr double kBaselineM = 0.5;
constexpr int kWidth = 64;
constexpr int kHeight = 32;

Frame StereoFrame(std::int64_t id, const Pose3d& world_from_cam) {
  Frame f;
  f.id = id;
  f.left = cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(10, 20, 30));
  f.right = cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(30, 20, 10));
  f.calibration.fx_px = kFocalPx;
  f.calibration.fy_px = kFocalPx;
  f.calibration.cx_px = kWidth / 2.0;
  f.calibration.cy_px = kHeight / 2.0;
  f.calibration.width_px = kWidth;
  f.calibration.height_px = kHeight;
  f.calibration.baseline_m = kBaselineM;
  f.world_from_cam = world_from_cam;
  return f;
}

Pose3d Translation(double x, double y, double z) {
  Pose3d p = Pose3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

TEST(RightView, SitsOneBaselineAlongTheLeftCamerasXWithTheSameIntrinsics) {
  Pose3d world_from_cam = Translation(1.0, 2.0, 3.0);
  world_from_cam.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Frame f = StereoFrame(4, world_from_cam);
  const CalibratedView right = RightView(f);
  EXPECT_EQ(right.image.type(), CV_8UC1);
  EXPECT_EQ(right.image.size(), f.right.size());
  EXPECT_DOUBLE_EQ(right.K(0, 0), kFocalPx);
  const Eigen::Vector3d in_left = world_from_cam.inverse() * right.world_from_cam.translation();
  EXPECT_NEAR((in_left - Eigen::Vector3d(kBaselineM, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(right.world_from_cam.linear().isApprox(world_from_cam.linear()));
}

TEST(PastFrameViews, GivesTheRightViewThenTheEarlierFramesNearestFirst) {
  PastFrameViews views(2);
  std::vector<Frame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(StereoFrame(i, Translation(0.0, 0.0, i)));
  for (Frame& f : frames) views.Attach(&f);
  ASSERT_EQ(frames[0].neighbour_views.size(), 1u);  // the right view only
  ASSERT_EQ(frames[1].neighbour_views.size(), 2u);
  EXPECT_EQ(frames[1].neighbour_views[1].frame_id, 0);
  ASSERT_EQ(frames[3].neighbour_views.size(), 3u);
  EXPECT_EQ(frames[3].neighbour_views[0].frame_id, 3);  // its own right view
  EXPECT_EQ(frames[3].neighbour_views[1].frame_id, 2);
  EXPECT_EQ(frames[3].neighbour_views[2].frame_id, 1);
  EXPECT_NEAR(frames[3].neighbour_views[2].world_from_cam.translation().z(), 1.0, 1e-12);
}

TEST(PastFrameViews, LeavesAFrameWithoutAPoseAloneAndDoesNotKeepIt) {
  PastFrameViews views(2);
  Frame first = StereoFrame(0, Translation(0.0, 0.0, 0.0));
  Frame lost = StereoFrame(1, Pose3d::Identity());
  lost.world_from_cam.reset();
  Frame third = StereoFrame(2, Translation(0.0, 0.0, 2.0));
  views.Attach(&first);
  views.Attach(&lost);
  views.Attach(&third);
  EXPECT_TRUE(lost.neighbour_views.empty());
  ASSERT_EQ(third.neighbour_views.size(), 2u);
  EXPECT_EQ(third.neighbour_views[1].frame_id, 0);
}

// The neighbour's image of the reference pixel's point at inverse depth w, by projecting it (the oracle the
// analytic derivative is checked against).
Eigen::Vector2d Project(const Frame& f, const CalibratedView& n, double u, double v, double w) {
  const Eigen::Vector3d ray((u - f.calibration.cx_px) / kFocalPx, (v - f.calibration.cy_px) / kFocalPx, 1.0);
  const Eigen::Vector3d in_n = n.world_from_cam.inverse() * (*f.world_from_cam * (ray / w));
  const Eigen::Vector3d x = n.K * in_n;
  return x.head<2>() / x.z();
}

TEST(SweepParallax, IsThePairsFocalTimesBaselineForTheRightViewAndMatchesProjectedPointsForAnEarlierFrame) {
  PastFrameViews views(1);
  Frame earlier = StereoFrame(0, Translation(0.1, 0.0, -2.0));
  Frame f = StereoFrame(1, Translation(0.0, 0.0, 0.0));
  f.world_from_cam->linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  views.Attach(&earlier);
  views.Attach(&f);
  ASSERT_EQ(f.neighbour_views.size(), 2u);
  constexpr double kInverseDepthPerM = 1.0 / 25.0;
  const cv::Mat w(kHeight, kWidth, CV_32F, cv::Scalar(kInverseDepthPerM));
  Frame right_only = f;
  right_only.neighbour_views.resize(1);
  const cv::Mat pair = SweepParallax(right_only, w, 2);
  EXPECT_NEAR(pair.at<float>(3, 50), kFocalPx * kBaselineM, 1e-3);
  const cv::Mat both = SweepParallax(f, w, 2);
  const cv::Mat best = SweepParallax(f, w, 1);
  constexpr double kStep = 1e-6;
  for (const auto& [u, v] : {std::pair{5, 3}, std::pair{32, 16}, std::pair{60, 30}}) {
    const CalibratedView& n = f.neighbour_views[1];
    const double expected =
        (Project(f, n, u, v, kInverseDepthPerM + kStep) - Project(f, n, u, v, kInverseDepthPerM)).norm() /
        kStep;
    const double pair_px_m = kFocalPx * kBaselineM;
    EXPECT_NEAR(both.at<float>(v, u), (expected + pair_px_m) / 2.0, 1e-2 * expected + 1e-2);
    EXPECT_NEAR(best.at<float>(v, u), std::max(expected, pair_px_m), 1e-2 * expected + 1e-2);
  }
}

// A frame with one earlier view far to the side (parallax 8 × the pair's everywhere) and SGBM's and the
// sweep's disparities given pixel by pixel.
struct CombineCase {
  Frame frame = StereoFrame(1, Translation(0.0, 0.0, 0.0));
  DisparityResult sgbm, swept;
  CombineCase() {
    Frame earlier = StereoFrame(0, Translation(-8.0 * kBaselineM, 0.0, 0.0));
    PastFrameViews views(1);
    views.Attach(&earlier);
    views.Attach(&frame);
    for (DisparityResult* r : {&sgbm, &swept}) {
      r->disparity_px = cv::Mat::zeros(kHeight, kWidth, CV_32F);
      r->confidence = cv::Mat::zeros(kHeight, kWidth, CV_32F);
    }
  }
  void Set(DisparityResult* r, int u, float disparity_px) {
    r->disparity_px.at<float>(0, u) = disparity_px;
    r->confidence.at<float>(0, u) = 0.5f;
  }
};

TEST(CombineStereoAndSweep, TakesTheSweepWhereItAgreesFarAwayAndKeepsSgbmNearWhereTheyDisagreeOrItHasNone) {
  CombineCase c;
  PlaneSweepOptions o;
  o.best_views = 1;  // the earlier frame's parallax, 8 × the pair's
  o.stereo_min_depth_m = 15.0;
  o.stereo_max_disagreement_px = 2.0;
  const float f_b = static_cast<float>(kFocalPx * kBaselineM);  // 350 px·m: 10 px at 35 m
  c.Set(&c.sgbm, 0, 10.0f), c.Set(&c.swept, 0, 11.0f);          // far, within the bound: the sweep's
  c.Set(&c.sgbm, 1, 10.0f), c.Set(&c.swept, 1, 13.0f);          // disagree by 3 px: SGBM's
  c.Set(&c.swept, 2, 9.0f);                                     // no SGBM: none
  c.Set(&c.sgbm, 3, f_b / 10.0f), c.Set(&c.swept, 3, f_b / 10.0f + 1.0f);  // SGBM at 10 m: SGBM's
  c.Set(&c.sgbm, 4, 12.0f);                                                // no sweep: SGBM's
  StereoSweepCounts counts;
  const DisparityResult out = CombineStereoAndSweep(c.frame, c.sgbm, c.swept, o, &counts);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 0), 11.0f);
  EXPECT_FLOAT_EQ(out.confidence.at<float>(0, 0), 1.0f);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 1), 10.0f);
  EXPECT_FLOAT_EQ(out.confidence.at<float>(0, 1), 0.5f);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 2), 0.0f);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 3), f_b / 10.0f);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 4), 12.0f);
  EXPECT_EQ(counts.replaced, 1);
  EXPECT_EQ(counts.sgbm, 3);

  o.stereo_max_disagreement_px = -1.0;  // no bound: the far pixel that disagrees is the sweep's too
  EXPECT_FLOAT_EQ(CombineStereoAndSweep(c.frame, c.sgbm, c.swept, o).disparity_px.at<float>(0, 1), 13.0f);
  o.stereo_parallax_gain = 9.0;  // beyond the earlier frame's parallax: SGBM alone
  const DisparityResult sgbm_only = CombineStereoAndSweep(c.frame, c.sgbm, c.swept, o);
  EXPECT_EQ(cv::countNonZero(sgbm_only.disparity_px != c.sgbm.disparity_px), 0);
}

TEST(CombineStereoAndSweep, GivesTheSweepsDepthAsThePairWouldHaveMeasuredItUnderADisparityOffset) {
  CombineCase c;
  c.frame.disparity_offset.constant_px = 0.5;  // true = measured + 0.5
  PlaneSweepOptions o;
  o.best_views = 1;
  c.Set(&c.sgbm, 0, 9.2f);
  c.Set(&c.swept, 0, 9.0f);  // the sweep's depth as true disparity
  const DisparityResult out = CombineStereoAndSweep(c.frame, c.sgbm, c.swept, o);
  EXPECT_FLOAT_EQ(out.disparity_px.at<float>(0, 0), 8.5f);
}

}  // namespace
}  // namespace semap
