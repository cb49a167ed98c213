#include "engine/semantics/labelling.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "engine/depth/stereo_depth.h"
#include "engine/pipeline/semap_stages.h"
#include "engine/semantics/segmenter.h"

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

// The depth stage's composition (as the pipeline's StereoLabelStage does it): SGBM cloud, the frame's
// label image from the configured source, the first-camera rule.
LabelledCloud DepthThenLabels(const Frame& f, const SemanticsOptions& semantics, LabellingReport* report) {
  DepthOptions o;
  o.num_disparities = 32;
  LabelledCloud cloud = StereoDepth(o).Process(f);
  const LabellingReport r = ApplyFirstCameraLabels(cloud, f.id, FrameLabels(f, semantics, nullptr),
                                                   f.left.size(), 0, semantics.size_mismatch);
  if (report) *report = r;
  return cloud;
}

TEST(StereoThenFirstCameraLabels, LabelsEachPointFromItsPixelInTheFramesLabelImage) {
  const Frame f = LabelledPlane();
  LabellingReport report;
  const LabelledCloud cloud = DepthThenLabels(f, SemanticsOptions{}, &report);
  ASSERT_GT(cloud.size(), 1000u);
  ASSERT_EQ(cloud.labels.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].y() < 60 ? 3 : 7) << "point " << i;
  }
  EXPECT_EQ(report.labelled, cloud.size());
  EXPECT_FALSE(report.resized);
}

TEST(StereoThenFirstCameraLabels, NoneSourceLeavesEveryPointUnlabelled) {
  const Frame f = LabelledPlane();
  SemanticsOptions s;
  s.source = LabelSource::kNone;
  const LabelledCloud cloud = DepthThenLabels(f, s, nullptr);
  ASSERT_GT(cloud.size(), 0u);
  EXPECT_EQ(cloud.labels, std::vector<Label>(cloud.size(), 0));
}

TEST(StereoThenFirstCameraLabels, LabelImageOfAnotherSizeIsResizedOrRefused) {
  Frame f = LabelledPlane();
  cv::resize(f.labels, f.labels, cv::Size(100, 60), 0, 0, cv::INTER_NEAREST);
  LabellingReport report;
  const LabelledCloud cloud = DepthThenLabels(f, SemanticsOptions{}, &report);
  EXPECT_TRUE(report.resized);
  for (size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].y() < 60 ? 3 : 7);
  SemanticsOptions refuse;
  refuse.size_mismatch = LabelSizePolicy::kRefuse;
  EXPECT_THROW(DepthThenLabels(f, refuse, nullptr), std::invalid_argument);
}

TEST(SkyLabel, IsTheClassNamedSky) {
  EXPECT_EQ(SkyLabel(ClassMap::Cityscapes()), Label(11));
  const ClassMap no_sky(
      "two", {{1, "road", {0, 0, 0}, ClassRole::kGround}, {2, "tree", {0, 0, 0}, ClassRole::kKeep}}, 0);
  EXPECT_FALSE(SkyLabel(no_sky).has_value());
  const ClassMap other_id("mine", {{5, "SKY", {0, 0, 0}, ClassRole::kKeep}}, 0);
  EXPECT_EQ(SkyLabel(other_id), Label(5));
}

TEST(RemoveLabel, RemovesExactlyThatLabelAndKeepsTheRestInOrder) {
  LabelledCloud c = TwoFrames();
  c.labels = {11, 3, 11, 7};
  EXPECT_EQ(RemoveLabel(c, 11), 2u);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.labels, (std::vector<Label>{3, 7}));
  EXPECT_EQ(c.positions_world[0], Eigen::Vector3d(1, 0, 1));
  EXPECT_EQ(c.positions_world[1], Eigen::Vector3d(3, 0, 1));
  EXPECT_EQ(c.camera_index, (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(RemoveLabel(c, 11), 0u);
  EXPECT_EQ(c.size(), 2u);
}

// The pipeline's depth stage on a plane whose upper half is labelled sky (Cityscapes 11): with
// semantics.drop_sky (the default) those pixels give no point, and the others are exactly the points the
// stage gives without it.
TEST(StereoLabelStage, SkyPixelsGiveNoPoint) {
  Frame f = LabelledPlane();
  f.labels.rowRange(0, 60).setTo(11);
  DepthOptions depth;
  depth.num_disparities = 32;
  depth.max_points_per_frame = 0;
  SemanticsOptions keep_sky;
  keep_sky.drop_sky = false;
  const LabelledCloud all = StereoLabelStage(depth, keep_sky, ClassMap::Cityscapes()).Process(f, nullptr);
  std::size_t sky_points = 0;
  for (size_t i = 0; i < all.size(); ++i) sky_points += all.pixels_px[i].y() < 59.5 ? 1 : 0;
  ASSERT_GT(sky_points, 1000u);
  ASSERT_LT(sky_points, all.size());

  ASSERT_TRUE(SemanticsOptions().drop_sky);
  const LabelledCloud no_sky =
      StereoLabelStage(depth, SemanticsOptions(), ClassMap::Cityscapes()).Process(f, nullptr);
  EXPECT_EQ(no_sky.size(), all.size() - sky_points);
  for (size_t i = 0; i < no_sky.size(); ++i) {
    EXPECT_NE(no_sky.labels[i], 11);
    EXPECT_GE(no_sky.pixels_px[i].y(), 59.5);
  }
  // Only sky in the frame: nothing to map, the frame is refused (the pipeline skips and counts it).
  f.labels.setTo(11);
  EXPECT_THROW(StereoLabelStage(depth, SemanticsOptions(), ClassMap::Cityscapes()).Process(f, nullptr),
               std::runtime_error);
}

}  // namespace
}  // namespace semap
