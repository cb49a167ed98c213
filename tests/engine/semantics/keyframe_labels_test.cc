#include "engine/semantics/keyframe_labels.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace semap {
namespace {

constexpr Label kUnlabelled = 255;

// A 64×40 camera, fx = fy = 100 px, principal point at the centre pixel (32, 20).
StereoCalibration SmallCamera() {
  StereoCalibration c;
  c.fx_px = 100.0;
  c.fy_px = 100.0;
  c.cx_px = 32.0;
  c.cy_px = 20.0;
  c.baseline_m = 0.5;
  c.width_px = 64;
  c.height_px = 40;
  return c;
}

// Labels that differ at every pixel of a row and every row: label(u, v) = (u + 64 v) mod 200.
cv::Mat Gradient(const StereoCalibration& c) {
  cv::Mat labels(c.height_px, c.width_px, CV_8UC1);
  for (int v = 0; v < c.height_px; ++v) {
    for (int u = 0; u < c.width_px; ++u)
      labels.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>((u + 64 * v) % 200);
  }
  return labels;
}

KeyframeLabels Keyframe(const StereoCalibration& c, const Pose3d& world_from_cam) {
  KeyframeLabels k;
  k.frame_id = 7;
  k.world_from_cam = world_from_cam;
  k.labels = Gradient(c);
  return k;
}

cv::Mat ConstantDepth(const StereoCalibration& c, float z_m) {
  return cv::Mat(c.height_px, c.width_px, CV_32FC1, cv::Scalar(z_m));
}

TEST(PropagateLabels, IdentityPoseGivesTheKeyframeLabels) {
  const StereoCalibration c = SmallCamera();
  const Pose3d pose =
      Pose3d(Eigen::Translation3d(3.0, -1.0, 12.0) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()));
  const KeyframeLabels k = Keyframe(c, pose);
  // With depth everywhere, and with no depth at all (points at infinity): the same image.
  for (const float z : {8.0f, 0.0f}) {
    PropagationReport report;
    const cv::Mat out = PropagateLabels(k, pose, ConstantDepth(c, z), c, kUnlabelled, &report);
    EXPECT_EQ(cv::countNonZero(out != k.labels), 0) << "z = " << z;
    EXPECT_EQ(report.outside, 0);
    EXPECT_EQ(report.with_depth + report.at_infinity, 64 * 40);
    EXPECT_EQ(report.with_depth, z > 0 ? 64 * 40 : 0);
  }
}

// The frame's camera 0.5 m to the right of the keyframe's (along its x): a point at depth z seen at pixel u
// in the frame is at u + fx·0.5 / z in the keyframe, here 100·0.5 / 10 = 5 px.
TEST(PropagateLabels, SidewaysTranslationShiftsByDisparity) {
  const StereoCalibration c = SmallCamera();
  const Pose3d world_from_keyframe = Pose3d(Eigen::Translation3d(1.0, 2.0, 3.0));
  const Pose3d world_from_frame = world_from_keyframe * Pose3d(Eigen::Translation3d(0.5, 0.0, 0.0));
  const KeyframeLabels k = Keyframe(c, world_from_keyframe);
  PropagationReport report;
  const cv::Mat out = PropagateLabels(k, world_from_frame, ConstantDepth(c, 10.0f), c, kUnlabelled, &report);
  for (int v = 0; v < c.height_px; ++v) {
    for (int u = 0; u < c.width_px; ++u) {
      const int expected = u + 5 < c.width_px ? (u + 5 + 64 * v) % 200 : kUnlabelled;
      ASSERT_EQ(out.at<std::uint8_t>(v, u), expected) << "pixel (" << u << ", " << v << ")";
    }
  }
  EXPECT_EQ(report.outside, 5 * 40);  // the 5 right-most columns fall outside the keyframe
}

// Points at infinity do not move with a translation, whatever its size.
TEST(PropagateLabels, PixelsWithoutDepthIgnoreTranslation) {
  const StereoCalibration c = SmallCamera();
  const KeyframeLabels k = Keyframe(c, Pose3d::Identity());
  cv::Mat depth = ConstantDepth(c, 0.0f);
  depth.at<float>(3, 4) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(5, 6) = std::numeric_limits<float>::infinity();
  depth.at<float>(7, 8) = -2.0f;
  const cv::Mat out = PropagateLabels(k, Pose3d(Eigen::Translation3d(4.0, 1.0, 30.0)), depth, c, kUnlabelled);
  EXPECT_EQ(cv::countNonZero(out != k.labels), 0);
}

// A yaw of the frame's camera by θ relative to the keyframe's: the frame's centre ray (0, 0, 1) is the
// keyframe's ray (sin θ, 0, cos θ), at u = cx + fx·tan θ = 32 + 100·tan(0.1) = 42.03 → pixel 42.
TEST(PropagateLabels, RotationMovesPointsAtInfinity) {
  const StereoCalibration c = SmallCamera();
  const Pose3d world_from_keyframe = Pose3d(Eigen::Translation3d(-2.0, 0.0, 5.0));
  const Pose3d world_from_frame =
      world_from_keyframe * Pose3d(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()));
  const KeyframeLabels k = Keyframe(c, world_from_keyframe);
  const cv::Mat out = PropagateLabels(k, world_from_frame, ConstantDepth(c, 0.0f), c, kUnlabelled);
  EXPECT_EQ(out.at<std::uint8_t>(20, 32), k.labels.at<std::uint8_t>(20, 42));
}

// Forward motion: the frame is 2 m ahead of the keyframe along its optical axis; a point at depth 8 m in the
// frame is at 10 m in the keyframe, so pixel offsets from the centre shrink by 8/10: (52, 30) → (48, 28).
TEST(PropagateLabels, ForwardMotionMovesPixelsTowardsTheCentre) {
  const StereoCalibration c = SmallCamera();
  const Pose3d world_from_frame = Pose3d(Eigen::Translation3d(0.0, 0.0, 2.0));
  const KeyframeLabels k = Keyframe(c, Pose3d::Identity());
  const cv::Mat out = PropagateLabels(k, world_from_frame, ConstantDepth(c, 8.0f), c, kUnlabelled);
  EXPECT_EQ(out.at<std::uint8_t>(30, 52), k.labels.at<std::uint8_t>(28, 48));
  EXPECT_EQ(out.at<std::uint8_t>(20, 32), k.labels.at<std::uint8_t>(20, 32));
  EXPECT_EQ(out.at<std::uint8_t>(10, 12), k.labels.at<std::uint8_t>(12, 16));
}

// A point behind the keyframe's camera (the frame looks backwards) is unlabelled.
TEST(PropagateLabels, PointsBehindTheKeyframeAreUnlabelled) {
  const StereoCalibration c = SmallCamera();
  const Pose3d world_from_frame = Pose3d(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()));
  const KeyframeLabels k = Keyframe(c, Pose3d::Identity());
  PropagationReport report;
  const cv::Mat out = PropagateLabels(k, world_from_frame, ConstantDepth(c, 5.0f), c, kUnlabelled, &report);
  EXPECT_EQ(cv::countNonZero(out != kUnlabelled), 0);
  EXPECT_EQ(report.outside, 64 * 40);
}

TEST(KeyframeSchedule, EveryNthFrameById) {
  KeyframeSchedule s(3);
  std::vector<std::int64_t> keyframes;
  for (std::int64_t id = 0; id < 10; ++id) {
    if (s.IsDue(id, true)) {
      s.Record(id, true);
      keyframes.push_back(id);
    }
  }
  EXPECT_EQ(keyframes, (std::vector<std::int64_t>{0, 3, 6, 9}));
}

TEST(KeyframeSchedule, OneMeansEveryFrame) {
  KeyframeSchedule s(1);
  for (std::int64_t id = 5; id < 9; ++id) {
    EXPECT_TRUE(s.IsDue(id, true));
    s.Record(id, true);
  }
}

// Ids missing from the stream (frames that failed to read): the first frame at least N ids on is due.
TEST(KeyframeSchedule, GapsInTheIdsAreCountedByIdNotByFrame) {
  KeyframeSchedule s(4);
  ASSERT_TRUE(s.IsDue(10, true));
  s.Record(10, true);
  EXPECT_FALSE(s.IsDue(11, true));
  EXPECT_FALSE(s.IsDue(13, true));
  EXPECT_TRUE(s.IsDue(15, true));  // 14 never came
}

TEST(KeyframeSchedule, FramesWithoutPoseAndRestartsAreKeyframes) {
  KeyframeSchedule s(10);
  s.Record(0, true);
  EXPECT_FALSE(s.IsDue(1, true));
  EXPECT_TRUE(s.IsDue(1, false));  // no pose: nothing to reproject with
  s.Record(1, false);
  EXPECT_TRUE(s.IsDue(2, true));  // its keyframe has no pose
  s.Record(2, true);
  EXPECT_FALSE(s.IsDue(3, true));
  EXPECT_TRUE(s.IsDue(0, true));  // the sequence starts over
}

// A refused keyframe (not recorded) leaves the next frame due.
TEST(KeyframeSchedule, RefusedKeyframeLeavesTheNextDue) {
  KeyframeSchedule s(2);
  s.Record(0, true);
  EXPECT_TRUE(s.IsDue(2, true));
  EXPECT_TRUE(s.IsDue(3, true));
}

TEST(LabelPropagation, Names) {
  EXPECT_STREQ(LabelPropagationName(LabelPropagation::kReproject), "reproject");
  EXPECT_STREQ(LabelPropagationName(LabelPropagation::kReuse), "reuse");
}

}  // namespace
}  // namespace semap
