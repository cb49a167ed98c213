#include "engine/depth/stereo_depth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "engine/core/check.h"

namespace semap {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 160;
constexpr int kTrueDisparity = 20;

// A textured left image and the right image of a fronto-parallel plane at disparity kTrueDisparity:
// left pixel u sees what right pixel u − d sees.
Frame PlaneFrame(int channels = 3) {
  cv::RNG rng(7);
  cv::Mat noise(kHeight, kWidth + kTrueDisparity, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0.8);
  Frame f;
  f.id = 42;
  const cv::Mat left = noise(cv::Rect(0, 0, kWidth, kHeight)).clone();
  const cv::Mat right = noise(cv::Rect(kTrueDisparity, 0, kWidth, kHeight)).clone();
  if (channels == 3) {
    cv::cvtColor(left, f.left, cv::COLOR_GRAY2BGR);
    cv::cvtColor(right, f.right, cv::COLOR_GRAY2BGR);
  } else {
    f.left = left;
    f.right = right;
  }
  f.calibration.fx_px = 400.0;
  f.calibration.fy_px = 400.0;
  f.calibration.cx_px = kWidth / 2.0;
  f.calibration.cy_px = kHeight / 2.0;
  f.calibration.baseline_m = 0.5;
  f.calibration.width_px = kWidth;
  f.calibration.height_px = kHeight;
  return f;
}

DepthOptions SmallOptions() {
  DepthOptions o;
  o.num_disparities = 32;
  o.min_depth_m = 1.0;
  o.max_depth_m = 40.0;
  o.max_points_per_frame = 0;  // these tests check the dense cloud (the budget is tested on its own)
  return o;
}

TEST(DepthOptions, DefaultsAreValid) { EXPECT_NO_THROW(DepthOptions{}.Check()); }

TEST(DepthOptions, RejectsOutOfRangeValuesNamingTheField) {
  auto expect_field = [](DepthOptions o, const std::string& field) {
    try {
      o.Check();
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidOption& e) {
      EXPECT_EQ(e.field(), field);
    }
  };
  DepthOptions o;
  o.num_disparities = 100;
  expect_field(o, "num_disparities");
  o = {};
  o.block_size = 4;
  expect_field(o, "block_size");
  o = {};
  o.p1 = 100;
  o.p2 = 50;
  expect_field(o, "p2");
  o = {};
  o.max_depth_m = 0.5;
  expect_field(o, "max_depth_m");
  o = {};
  o.min_depth_m = 0.0;
  expect_field(o, "min_depth_m");
  o = {};
  o.pixel_stride = 0;
  expect_field(o, "pixel_stride");
  o = {};
  o.left_right_max_diff_px = -2.0f;
  expect_field(o, "left_right_max_diff_px");
  o = {};
  o.min_point_confidence = 1.5f;
  expect_field(o, "min_point_confidence");
  o = {};
  o.disp12_max_diff_px = -3;
  EXPECT_THROW(StereoDepth{o}, InvalidOption);
}

// Share of pixels in the matchable interior whose disparity is within tol of the truth.
double ShareCorrect(const cv::Mat& disparity, double truth, double tol, int margin) {
  int good = 0, total = 0;
  for (int v = margin; v < disparity.rows - margin; ++v) {
    for (int u = 64 + margin; u < disparity.cols - margin; ++u) {
      ++total;
      if (std::abs(disparity.at<float>(v, u) - truth) <= tol) ++good;
    }
  }
  return double(good) / total;
}

TEST(StereoDepth, RecoversTheDisparityOfAPlane) {
  const Frame f = PlaneFrame();
  const StereoDepth depth(SmallOptions());
  const DisparityResult r = depth.Compute(f.left, f.right);
  ASSERT_EQ(r.disparity_px.type(), CV_32FC1);
  ASSERT_EQ(r.disparity_px.size(), f.left.size());
  ASSERT_EQ(r.confidence.size(), f.left.size());
  EXPECT_GT(ShareCorrect(r.disparity_px, kTrueDisparity, 0.5, 8), 0.95);
}

TEST(StereoDepth, GrayscalePairsWorkToo) {
  const Frame f = PlaneFrame(1);
  const StereoDepth depth(SmallOptions());
  EXPECT_GT(ShareCorrect(depth.ComputeDisparity(f.left, f.right), kTrueDisparity, 0.5, 8), 0.95);
}

TEST(StereoDepth, HalfResolutionReturnsFullSizeDisparityInFullResolutionPixels) {
  const Frame f = PlaneFrame();
  DepthOptions o = SmallOptions();
  o.half_resolution = true;
  const cv::Mat d = StereoDepth(o).ComputeDisparity(f.left, f.right);
  ASSERT_EQ(d.size(), f.left.size());
  EXPECT_GT(ShareCorrect(d, kTrueDisparity, 1.0, 8), 0.9);
}

TEST(StereoDepth, ExplicitLeftRightCheckKeepsConsistentMatches) {
  const Frame f = PlaneFrame();
  DepthOptions o = SmallOptions();
  o.left_right_max_diff_px = 1.0f;
  o.fill_left_border = false;
  o.fill_max_gap_px = 0;
  const cv::Mat d = StereoDepth(o).ComputeDisparity(f.left, f.right);
  EXPECT_GT(ShareCorrect(d, kTrueDisparity, 0.5, 8), 0.9);
}

// A background at disparity kBackgroundPx with a foreground block at kForegroundPx in front of it: the
// background just left of the block is seen by the left camera only (the block hides it from the right one):
// the band [block's left edge − (kForegroundPx − kBackgroundPx), block's left edge) has no true match.
constexpr int kBackgroundPx = 8, kForegroundPx = 24;
const cv::Rect kBlock(150, 40, 80, 80);  // in the left image
Frame StepFrame() {
  cv::RNG rng(11);
  cv::Mat background(kHeight, kWidth + kForegroundPx, CV_8UC1),
      foreground(kHeight, kWidth + kForegroundPx, CV_8UC1);
  rng.fill(background, cv::RNG::UNIFORM, 0, 255);
  rng.fill(foreground, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(background, background, cv::Size(3, 3), 0.8);
  cv::GaussianBlur(foreground, foreground, cv::Size(3, 3), 0.8);
  Frame f = PlaneFrame(1);
  f.left = background(cv::Rect(0, 0, kWidth, kHeight)).clone();
  f.right = background(cv::Rect(kBackgroundPx, 0, kWidth, kHeight)).clone();
  foreground(kBlock).copyTo(f.left(kBlock));  // left pixel u of the block shows foreground u
  const cv::Rect in_right(kBlock.x - kForegroundPx, kBlock.y, kBlock.width, kBlock.height);
  foreground(kBlock).copyTo(f.right(in_right));  // right pixel u − kForegroundPx shows it too
  return f;
}

// The share of the pixels of `region` with a disparity (> 0), and the share within 1 px of `truth`.
std::pair<double, double> ValidAndCorrect(const cv::Mat& disparity, const cv::Rect& region, double truth) {
  int valid = 0, correct = 0;
  for (int v = region.y; v < region.y + region.height; ++v) {
    for (int u = region.x; u < region.x + region.width; ++u) {
      const float d = disparity.at<float>(v, u);
      valid += d > 0.0f;
      correct += std::abs(d - truth) <= 1.0;
    }
  }
  const double n = double(region.area());
  return {valid / n, correct / n};
}

// The left-right check drops the pixels the right camera cannot see (the background beside the block); its
// right-image pass at half resolution does as well, and keeps the matched pixels of both surfaces.
TEST(StereoDepth, LeftRightCheckAtHalfResolutionDropsTheOccludedBand) {
  const Frame f = StepFrame();
  DepthOptions o = SmallOptions();
  o.fill_left_border = false;
  o.fill_max_gap_px = 0;
  o.speckle_window_size = 0;
  o.uniqueness_ratio = 0;  // so that SGBM matches the band too, wrongly
  const cv::Rect band(kBlock.x - (kForegroundPx - kBackgroundPx), kBlock.y + 4, kForegroundPx - kBackgroundPx,
                      kBlock.height - 8);
  const cv::Rect block_inside(kBlock.x + 8, kBlock.y + 8, kBlock.width - 16, kBlock.height - 16);
  const cv::Rect background(40, 8, 80, 24);  // above the block, away from it
  const cv::Mat unchecked = StereoDepth(o).ComputeDisparity(f.left, f.right);
  o.left_right_max_diff_px = 2.0f;
  const cv::Mat full = StereoDepth(o).ComputeDisparity(f.left, f.right);
  o.left_right_half_resolution = true;
  const cv::Mat half = StereoDepth(o).ComputeDisparity(f.left, f.right);
  // Measured: 10 % of the band has a (wrong) disparity unchecked, 5 % after the full check, 2 % after the
  // half-resolution one; both keep every pixel of the block's and the background's insides.
  const double band_unchecked = ValidAndCorrect(unchecked, band, kBackgroundPx).first;
  EXPECT_GT(band_unchecked, 0.05) << "the band must have wrong matches for the check to remove";
  EXPECT_LT(ValidAndCorrect(full, band, kBackgroundPx).first, 0.75 * band_unchecked);
  EXPECT_LT(ValidAndCorrect(half, band, kBackgroundPx).first, 0.5 * band_unchecked);
  for (const cv::Mat* d : {&full, &half}) {
    EXPECT_GT(ValidAndCorrect(*d, block_inside, kForegroundPx).second, 0.95);
    EXPECT_GT(ValidAndCorrect(*d, background, kBackgroundPx).second, 0.95);
  }
}

TEST(StereoDepth, CloudHasTheDepthOfThePlaneInTheWorldFrame) {
  Frame f = PlaneFrame();
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  world_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  f.world_from_cam = world_from_cam;
  const StereoDepth depth(SmallOptions());
  const LabelledCloud cloud = depth.Process(f);
  cloud.AssertConsistent();
  ASSERT_GT(cloud.size(), 0.8 * kWidth * kHeight * (kWidth - 32.0) / kWidth);
  ASSERT_EQ(cloud.camera_centers_world.size(), 1u);
  EXPECT_TRUE(cloud.camera_centers_world[0].isApprox(world_from_cam.translation()));
  EXPECT_EQ(cloud.camera_frame_ids, std::vector<std::int64_t>{42});
  EXPECT_EQ(cloud.pixels_px.size(), cloud.size());
  EXPECT_EQ(cloud.colors_rgb.size(), cloud.size());
  EXPECT_EQ(cloud.confidence.size(), cloud.size());
  EXPECT_TRUE(cloud.labels.empty());
  const double true_z = f.calibration.DepthFromDisparity(kTrueDisparity);  // 10 m
  const Pose3d cam_from_world = world_from_cam.inverse();
  int close = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p_cam = cam_from_world * cloud.positions_world[i];
    ASSERT_TRUE(p_cam.allFinite());
    // The point reprojects onto its own pixel.
    const Eigen::Vector2d uv = f.calibration.Project(p_cam);
    EXPECT_NEAR(uv.x(), cloud.pixels_px[i].x(), 1e-6);
    EXPECT_NEAR(uv.y(), cloud.pixels_px[i].y(), 1e-6);
    EXPECT_EQ(cloud.confidence[i], 1.0f);  // default: matched pixels only
    if (std::abs(p_cam.z() - true_z) < 0.25) ++close;
  }
  EXPECT_GT(close, 0.95 * cloud.size());
}

TEST(StereoDepth, ColoursAreRgbOfTheLeftPixel) {
  Frame f = PlaneFrame();
  f.left.setTo(cv::Scalar(10, 20, 30));  // BGR
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(10.0f));
  const LabelledCloud cloud = StereoDepth(SmallOptions()).ToCloud(f, disparity);
  ASSERT_EQ(cloud.size(), size_t(kWidth * kHeight));
  EXPECT_EQ(cloud.colors_rgb[0], (std::array<std::uint8_t, 3>{30, 20, 10}));
  EXPECT_EQ(cloud.camera_index, std::vector<std::uint32_t>(cloud.size(), 0));
}

TEST(StereoDepth, InvalidDisparitiesNeverGiveAPoint) {
  const Frame f = PlaneFrame();
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(0.0f));
  disparity.at<float>(0, 0) = -1.0f;
  disparity.at<float>(0, 1) = std::numeric_limits<float>::quiet_NaN();
  disparity.at<float>(0, 2) = std::numeric_limits<float>::infinity();
  disparity.at<float>(0, 3) = -std::numeric_limits<float>::infinity();
  disparity.at<float>(0, 4) = 1e-30f;  // would be a point at ~infinity
  disparity.at<float>(5, 6) = 20.0f;   // the one valid pixel: 10 m
  const LabelledCloud cloud = StereoDepth(SmallOptions()).ToCloud(f, disparity);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_NEAR(cloud.positions_world[0].z(), 10.0, 1e-9);
  EXPECT_EQ(cloud.pixels_px[0], Eigen::Vector2f(6, 5));
}

// The frame's rectification offset is added to every measured disparity: fB / (d + offset), in the cloud and
// in the view the map votes from; a pixel without a measured disparity stays without a point.
TEST(StereoDepth, TheFramesDisparityOffsetCorrectsEveryDepth) {
  Frame f = PlaneFrame();
  f.disparity_offset.constant_px = 0.5;
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(0.0f));
  disparity.at<float>(5, 6) = 19.5f;  // fB = 200 px·m: (19.5 + 0.5) px → 10 m
  disparity.at<float>(7, 8) = 9.5f;   // → 20 m
  const StereoDepth depth(SmallOptions());
  const LabelledCloud cloud = depth.ToCloud(f, disparity);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_NEAR(cloud.positions_world[0].z(), 10.0, 1e-5);
  EXPECT_NEAR(cloud.positions_world[1].z(), 20.0, 1e-5);
  const DepthView view = depth.ToDepthView(f, disparity);
  EXPECT_NEAR(view.depth_m.at<float>(5, 6), 10.0f, 1e-5);
  EXPECT_NEAR(view.depth_m.at<float>(7, 8), 20.0f, 1e-5);
  EXPECT_EQ(view.depth_m.at<float>(0, 0), 0.0f);  // no disparity measured: no depth, whatever the offset
  EXPECT_EQ(cv::countNonZero(view.depth_m), 2);
  // A per-row term: the offset at row v is 0.5 + 0.8 (v − cy) / fy; row 0 is cy / fy = 0.2 above centre.
  f.disparity_offset.per_row_px = 0.8;
  const double offset_row0_px = 0.5 + 0.8 * (0.0 - f.calibration.cy_px) / f.calibration.fy_px;
  cv::Mat row0(f.left.size(), CV_32F, cv::Scalar(0.0f));
  row0.at<float>(0, 3) = static_cast<float>(20.0 - offset_row0_px);  // → 10 m
  const LabelledCloud tilted = depth.ToCloud(f, row0);
  ASSERT_EQ(tilted.size(), 1u);
  EXPECT_NEAR(tilted.positions_world[0].z(), 10.0, 1e-4);
  EXPECT_NEAR(depth.ToDepthView(f, row0).depth_m.at<float>(0, 3), 10.0f, 1e-4);
}

TEST(StereoDepth, DepthRangeIsEnforced) {
  const Frame f = PlaneFrame();
  DepthOptions o = SmallOptions();
  o.min_depth_m = 5.0;
  o.max_depth_m = 20.0;
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(0.0f));
  // fB = 200 px·m: disparities 100 → 2 m, 40 → 5 m, 20 → 10 m, 10 → 20 m, 5 → 40 m.
  const float values[] = {100.0f, 40.0f, 20.0f, 10.0f, 5.0f};
  for (int i = 0; i < 5; ++i) disparity.at<float>(0, i) = values[i];
  const LabelledCloud cloud = StereoDepth(o).ToCloud(f, disparity);
  ASSERT_EQ(cloud.size(), 3u);
  for (const auto& p : cloud.positions_world) {
    EXPECT_GE(p.z(), 5.0 - 1e-9);
    EXPECT_LE(p.z(), 20.0 + 1e-9);
  }
}

TEST(StereoDepth, StrideAndPointBudget) {
  const Frame f = PlaneFrame();
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(20.0f));
  DepthOptions o = SmallOptions();
  o.pixel_stride = 4;
  const LabelledCloud strided = StereoDepth(o).ToCloud(f, disparity);
  EXPECT_EQ(strided.size(), size_t((kWidth / 4) * (kHeight / 4)));
  for (const auto& px : strided.pixels_px) {
    EXPECT_EQ(int(px.x()) % 4, 0);
    EXPECT_EQ(int(px.y()) % 4, 0);
  }
  o.half_resolution = true;  // doubles the stride: one point per half-resolution pixel
  EXPECT_EQ(StereoDepth(o).ToCloud(f, disparity).size(), size_t((kWidth / 8) * (kHeight / 8)));
  o.half_resolution = false;
  o.pixel_stride = 1;
  o.max_points_per_frame = 1000;
  const LabelledCloud budget = StereoDepth(o).ToCloud(f, disparity);
  EXPECT_EQ(budget.size(), 1000u);
  budget.AssertConsistent();
  // Spread over the whole image, not the first rows only.
  EXPECT_GT(budget.pixels_px.back().y(), kHeight - 2);
}

TEST(StereoDepth, LowConfidencePixelsAreDroppedOnRequest) {
  const Frame f = PlaneFrame();
  cv::Mat disparity(f.left.size(), CV_32F, cv::Scalar(20.0f));
  cv::Mat confidence(f.left.size(), CV_32F, cv::Scalar(1.0f));
  confidence.rowRange(0, 10).setTo(0.5f);
  DepthOptions o = SmallOptions();
  EXPECT_EQ(StereoDepth(o).ToCloud(f, disparity, confidence).size(), size_t(kWidth * (kHeight - 10)));
  o.min_point_confidence = 0.5f;
  EXPECT_EQ(StereoDepth(o).ToCloud(f, disparity, confidence).size(), size_t(kWidth * kHeight));
}

TEST(StereoDepth, TexturelessPairGivesNoPointsButKeepsItsCamera) {
  Frame f = PlaneFrame();
  f.left.setTo(cv::Scalar(128, 128, 128));
  f.right.setTo(cv::Scalar(128, 128, 128));
  DepthOptions o = SmallOptions();
  o.uniqueness_ratio = 10;
  const LabelledCloud cloud = StereoDepth(o).Process(f);
  EXPECT_TRUE(cloud.empty());
  EXPECT_EQ(cloud.camera_centers_world.size(), 1u);
  cloud.AssertConsistent();
}

TEST(StereoDepth, ImagesNarrowerThanTheSearchRangeGiveNoDisparity) {
  // OpenCV 4.6's 3-way SGBM aborts the process on these; the stage must not call it.
  for (const SgbmMode mode : {SgbmMode::kThreeWay, SgbmMode::kSgbm, SgbmMode::kHh, SgbmMode::kHh4}) {
    for (const int width : {8, 32, 64}) {
      DepthOptions o;
      o.num_disparities = 64;
      o.mode = mode;
      const Frame f = PlaneFrame();
      const cv::Mat left = f.left.colRange(0, width).clone();
      const cv::Mat right = f.right.colRange(0, width).clone();
      const cv::Mat d = StereoDepth(o).ComputeDisparity(left, right);
      ASSERT_EQ(d.size(), left.size());
      EXPECT_EQ(cv::countNonZero(d), 0) << SgbmModeName(mode) << " width " << width;
      o.half_resolution = true;
      EXPECT_EQ(cv::countNonZero(StereoDepth(o).ComputeDisparity(left, right)), 0);
    }
  }
  const Frame f = PlaneFrame();
  DepthOptions o;
  o.num_disparities = 32;
  EXPECT_EQ(StereoDepth(o).ComputeDisparity(f.left.rowRange(0, 1), f.right.rowRange(0, 1)).rows, 1);
}

TEST(StereoDepth, BadPairsThrowClearErrors) {
  const Frame f = PlaneFrame();
  const StereoDepth depth(SmallOptions());
  auto message = [&](const cv::Mat& l, const cv::Mat& r) -> std::string {
    try {
      depth.Compute(l, r);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message(f.left, f.right(cv::Rect(0, 0, 100, 100)).clone()).find("sizes differ"),
            std::string::npos);
  cv::Mat gray;
  cv::cvtColor(f.right, gray, cv::COLOR_BGR2GRAY);
  EXPECT_NE(message(f.left, gray).find("grayscale/colour"), std::string::npos);
  EXPECT_NE(message(cv::Mat(), f.right).find("left image is empty"), std::string::npos);
  EXPECT_NE(message(f.left, cv::Mat()).find("right image is empty"), std::string::npos);
  cv::Mat f32l, f32r;
  f.left.convertTo(f32l, CV_32FC3);
  f.right.convertTo(f32r, CV_32FC3);
  EXPECT_NE(message(f32l, f32r).find("8-bit"), std::string::npos);
}

TEST(StereoDepth, ToCloudRejectsMismatchedInputs) {
  Frame f = PlaneFrame();
  const StereoDepth depth(SmallOptions());
  EXPECT_THROW(depth.ToCloud(f, cv::Mat(10, 10, CV_32F, cv::Scalar(1.0f))), std::invalid_argument);
  EXPECT_THROW(depth.ToCloud(f, cv::Mat(f.left.size(), CV_16S, cv::Scalar(1))), std::invalid_argument);
  EXPECT_THROW(depth.ToCloud(f, cv::Mat()), std::invalid_argument);
  const cv::Mat d(f.left.size(), CV_32F, cv::Scalar(1.0f));
  EXPECT_THROW(depth.ToCloud(f, d, cv::Mat(3, 3, CV_32F)), std::invalid_argument);
  f.calibration.baseline_m = 0.0;
  EXPECT_THROW(depth.ToCloud(f, d), std::invalid_argument);
}

}  // namespace
}  // namespace semap
