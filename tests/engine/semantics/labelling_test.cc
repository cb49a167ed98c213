#include "engine/semantics/labelling.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

constexpr Label kUnlabelled = 0;

// Two frames' points: frame 10 (camera 0) and frame 11 (camera 1), pixels in a 4×3 image.
LabelledCloud TwoFrames() {
  LabelledCloud c;
  c.positions_world = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {3, 0, 1}};
  c.pixels_px = {{0, 0}, {3, 2}, {0, 0}, {9, 9}};
  c.camera_index = {0, 0, 1, 1};
  c.camera_centers_world = {{0, 0, 0}, {1, 0, 0}};
  c.camera_frame_ids = {10, 11};
  return c;
}

cv::Mat Labels(Label fill) { return cv::Mat(3, 4, CV_8UC1, cv::Scalar(fill)); }

TEST(FirstCameraLabels, LabelsOnlyThePointsBornInThatFrame) {
  LabelledCloud c = TwoFrames();
  cv::Mat l10 = Labels(7);
  l10.at<Label>(2, 3) = 9;
  const auto r = ApplyFirstCameraLabels(c, 10, l10, {4, 3}, kUnlabelled);
  EXPECT_EQ(c.labels, (std::vector<Label>{7, 9, kUnlabelled, kUnlabelled}));
  EXPECT_EQ(r.labelled, 2u);
  EXPECT_EQ(r.other_cameras, 2u);
  EXPECT_FALSE(r.resized);
}

TEST(FirstCameraLabels, AReobservedPointKeepsItsFirstLabel) {
  LabelledCloud c = TwoFrames();
  ApplyFirstCameraLabels(c, 10, Labels(7), {4, 3}, kUnlabelled);
  // Frame 11's segmentation says 3 everywhere, including where frame 10's points are seen again: they keep 7.
  ApplyFirstCameraLabels(c, 11, Labels(3), {4, 3}, kUnlabelled);
  EXPECT_EQ(c.labels[0], 7);
  EXPECT_EQ(c.labels[1], 7);
  EXPECT_EQ(c.labels[2], 3);
  // Re-applying frame 10's labels after frame 11's never touches frame 11's points.
  ApplyFirstCameraLabels(c, 10, Labels(5), {4, 3}, kUnlabelled);
  EXPECT_EQ(c.labels[2], 3);
  // The merge rule itself.
  EXPECT_EQ(KeepFirstLabel(std::optional<Label>(7), 3), 7);
  EXPECT_EQ(KeepFirstLabel(std::nullopt, 3), 3);
}

TEST(FirstCameraLabels, PixelsOutsideTheImageAreUnlabelled) {
  LabelledCloud c = TwoFrames();
  const auto r = ApplyFirstCameraLabels(c, 11, Labels(3), {4, 3}, kUnlabelled);
  EXPECT_EQ(c.labels[2], 3);
  EXPECT_EQ(c.labels[3], kUnlabelled);  // pixel (9, 9)
  EXPECT_EQ(r.outside_image, 1u);
}

TEST(FirstCameraLabels, NoLabelImageMeansUnlabelled) {
  LabelledCloud c = TwoFrames();
  c.labels = {4, 4, 4, 4};
  ApplyFirstCameraLabels(c, 10, cv::Mat(), {4, 3}, kUnlabelled);
  EXPECT_EQ(c.labels, (std::vector<Label>{kUnlabelled, kUnlabelled, 4, 4}));
}

TEST(FirstCameraLabels, OtherSizeIsResizedNearestAndReportedOrRefused) {
  LabelledCloud c = TwoFrames();
  // A 2× label image: left half 1, right half 2 (8×6 for a 4×3 image).
  cv::Mat big(6, 8, CV_8UC1, cv::Scalar(1));
  big.colRange(4, 8).setTo(2);
  const auto r = ApplyFirstCameraLabels(c, 10, big, {4, 3}, kUnlabelled);
  EXPECT_TRUE(r.resized);
  EXPECT_EQ(c.labels[0], 1);  // pixel (0, 0)
  EXPECT_EQ(c.labels[1], 2);  // pixel (3, 2)
  try {
    ApplyFirstCameraLabels(c, 10, big, {4, 3}, kUnlabelled, LabelSizePolicy::kRefuse);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("8x6"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("4x3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ApplyFirstCameraLabels(c, 10, cv::Mat(3, 4, CV_16UC1), {4, 3}, kUnlabelled),
               std::invalid_argument);
}

TEST(ColorizeLabels, UsesTheClassColoursAndBlendsOverTheImage) {
  const ClassMap cityscapes = ClassMap::Cityscapes();
  cv::Mat labels(2, 2, CV_8UC1, cv::Scalar(1));  // Road (81, 0, 81)
  labels.at<Label>(1, 1) = 200;                  // unknown id → black
  const cv::Mat colour = ColorizeLabels(labels, cityscapes);
  EXPECT_EQ(colour.at<cv::Vec3b>(0, 0), cv::Vec3b(81, 0, 81));
  EXPECT_EQ(colour.at<cv::Vec3b>(1, 1), cv::Vec3b(0, 0, 0));
  const cv::Mat grey(2, 2, CV_8UC1, cv::Scalar(100));
  const cv::Mat overlay = OverlayLabels(grey, labels, cityscapes, 0.5);
  EXPECT_EQ(overlay.type(), CV_8UC3);
  EXPECT_EQ(overlay.at<cv::Vec3b>(1, 1), cv::Vec3b(50, 50, 50));
  EXPECT_THROW(OverlayLabels(cv::Mat(3, 3, CV_8UC1), labels, cityscapes, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace semap
