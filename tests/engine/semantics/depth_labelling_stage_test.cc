#include "engine/semantics/depth_labelling_stage.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace semap {
namespace {

// A textured fronto-parallel plane at disparity 16 px with a label image: top half 3, bottom half 7.
Frame LabelledPlane() {
  cv::RNG rng(3);
  cv::Mat noise(120, 216, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0.8);
  Frame f;
  f.id = 5;
  f.left = noise(cv::Rect(0, 0, 200, 120)).clone();
  f.right = noise(cv::Rect(16, 0, 200, 120)).clone();
  f.calibration = {300.0, 300.0, 100.0, 60.0, 0.5, 200, 120};
  f.labels = cv::Mat(120, 200, CV_8UC1, cv::Scalar(3));
  f.labels.rowRange(60, 120).setTo(7);
  return f;
}

DepthOptions SmallDepth() {
  DepthOptions o;
  o.num_disparities = 32;
  return o;
}

TEST(DepthLabellingStage, LabelsEachPointFromItsPixelInTheFramesLabelImage) {
  const Frame f = LabelledPlane();
  DepthLabellingStage stage(SmallDepth(), SemanticsOptions{}, 0);
  const LabelledCloud cloud = stage.Process(f);
  ASSERT_GT(cloud.size(), 1000u);
  ASSERT_EQ(cloud.labels.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].y() < 60 ? 3 : 7) << "point " << i;
  }
  EXPECT_EQ(stage.last_report().labelled, cloud.size());
  EXPECT_FALSE(stage.last_report().resized);
}

TEST(DepthLabellingStage, NoneSourceLeavesEveryPointUnlabelled) {
  const Frame f = LabelledPlane();
  SemanticsOptions s;
  s.source = LabelSource::kNone;
  DepthLabellingStage stage(SmallDepth(), s, 0);
  const LabelledCloud cloud = stage.Process(f);
  ASSERT_GT(cloud.size(), 0u);
  EXPECT_EQ(cloud.labels, std::vector<Label>(cloud.size(), 0));
}

TEST(DepthLabellingStage, LabelImageOfAnotherSizeIsResizedOrRefused) {
  Frame f = LabelledPlane();
  cv::resize(f.labels, f.labels, cv::Size(100, 60), 0, 0, cv::INTER_NEAREST);
  DepthLabellingStage stage(SmallDepth(), SemanticsOptions{}, 0);
  const LabelledCloud cloud = stage.Process(f);
  EXPECT_TRUE(stage.last_report().resized);
  for (size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].y() < 60 ? 3 : 7);
  SemanticsOptions refuse;
  refuse.size_mismatch = LabelSizePolicy::kRefuse;
  DepthLabellingStage strict(SmallDepth(), refuse, 0);
  EXPECT_THROW(strict.Process(f), std::invalid_argument);
}

}  // namespace
}  // namespace semap
