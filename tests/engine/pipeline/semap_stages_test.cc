// StereoLabelStage with keyframe labels (a pipeline with a segment stage) and SegmenterStage. The
// frame-label path without keyframes is tested with the labelling rule (tests/engine/semantics/labelling_test.cc).
#include "engine/pipeline/semap_stages.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace semap {
namespace {

constexpr Label kRoad = 7;      // Cityscapes ids (none of them sky)
constexpr Label kBuilding = 3;
constexpr Label kUnlabelled = 0;  // Cityscapes' unlabelled id

// A textured fronto-parallel plane at disparity 16 px: depth fx·B/16 = 300·0.5/16 = 9.375 m. The frame's
// own label image (which keyframe labels must override) is all 1.
Frame Plane(std::int64_t id, const Pose3d& world_from_cam) {
  cv::RNG rng(3);
  cv::Mat noise(120, 216, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0.8);
  Frame f;
  f.id = id;
  f.left = noise(cv::Rect(0, 0, 200, 120)).clone();
  f.right = noise(cv::Rect(16, 0, 200, 120)).clone();
  f.calibration = {300.0, 300.0, 100.0, 60.0, 0.5, 200, 120};
  f.world_from_cam = world_from_cam;
  f.labels = cv::Mat(120, 200, CV_8UC1, cv::Scalar(1));
  return f;
}

// Keyframe 10 at the origin: columns u < 100 building, u >= 100 road.
KeyframeLabels SplitKeyframe() {
  KeyframeLabels k;
  k.frame_id = 10;
  k.world_from_cam = Pose3d::Identity();
  k.labels = cv::Mat(120, 200, CV_8UC1, cv::Scalar(kBuilding));
  k.labels.colRange(100, 200).setTo(kRoad);
  return k;
}

DepthOptions SmallDepth() {
  DepthOptions depth;
  depth.num_disparities = 32;
  depth.max_points_per_frame = 0;
  return depth;
}

SemanticsOptions Enet(LabelPropagation propagation) {
  SemanticsOptions s;
  s.source = LabelSource::kEnet;
  s.enet_model_path = "/nonexistent/enet-model.net";  // never loaded with keyframe labels
  s.enet_propagation = propagation;
  return s;
}

// On the keyframe itself, its labels are the frame's, whatever the frame's own label image.
TEST(StereoLabelStageKeyframes, AKeyframeTakesItsOwnLabels) {
  StereoLabelStage stage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true);
  const KeyframeLabels keyframe = SplitKeyframe();
  const LabelledCloud cloud = stage.Process(Plane(10, Pose3d::Identity()), &keyframe);
  ASSERT_GT(cloud.size(), 1000u);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].x() < 99.5 ? kBuilding : kRoad) << cloud.pixels_px[i].x();
  }
}

// The frame 0.25 m to the right of the keyframe: a point of the plane (9.375 m) at column u of the frame is at
// u + 300·0.25/9.375 = u + 8 in the keyframe: building up to u = 91, road from 92, unlabelled beyond 191.
// Reused labels keep the keyframe's columns.
TEST(StereoLabelStageKeyframes, AFrameBetweenKeyframesTakesTheReprojectedOrReusedLabels) {
  const Frame frame = Plane(12, Pose3d(Eigen::Translation3d(0.25, 0.0, 0.0)));
  const KeyframeLabels keyframe = SplitKeyframe();
  const LabelledCloud reprojected =
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true)
          .Process(frame, &keyframe);
  const LabelledCloud reused =
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReuse), ClassMap::Cityscapes(), true)
          .Process(frame, &keyframe);
  ASSERT_GT(reprojected.size(), 1000u);
  ASSERT_EQ(reused.size(), reprojected.size());
  size_t moved = 0;
  for (size_t i = 0; i < reprojected.size(); ++i) {
    const double u = reprojected.pixels_px[i].x();
    if (u < 91.0) {
      EXPECT_EQ(reprojected.labels[i], kBuilding) << u;
    }
    if (u > 93.0 && u < 191.0) {
      EXPECT_EQ(reprojected.labels[i], kRoad) << u;
    }
    if (u > 193.0) {
      EXPECT_EQ(reprojected.labels[i], kUnlabelled) << u;
    }
    if (u > 93.0 && u < 99.0) ++moved;
    EXPECT_EQ(reused.labels[i], u < 99.5 ? kBuilding : kRoad) << u;
  }
  EXPECT_GT(moved, 100u);  // the band that reprojection relabels exists
}

// The depth workers of a pipeline with a segment stage load no model: a wrong path is no error there; the
// segment stage loads it and names the file.
TEST(SegmenterStage, LoadsTheModelAtConstruction) {
  EXPECT_NO_THROW(StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true));
  try {
    SegmenterStage stage(Enet(LabelPropagation::kReproject));
    FAIL() << "no error for a missing model";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/enet-model.net"), std::string::npos) << e.what();
  }
  EXPECT_THROW(StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), false),
               std::runtime_error);
}

}  // namespace
}  // namespace semap
