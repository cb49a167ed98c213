#include "engine/eval/error_image.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

TEST(ErrorImage, ColoursReferencePixelsByErrorHolesBlackTheRestGreyWithALegend) {
  constexpr int kW = 400, kH = 60;
  cv::Mat reference(kH, kW, CV_32F, cv::Scalar(0.0f));
  cv::Mat mesh(kH, kW, CV_32F, cv::Scalar(10.0f));
  reference.at<float>(10, 10) = 10.0f;   // no error
  reference.at<float>(10, 50) = 5.0f;    // 5 m: beyond the scale
  reference.at<float>(10, 90) = 9.0f;    // 1 m: mid-scale
  reference.at<float>(40, 200) = 10.0f;  // a hole
  mesh.at<float>(40, 200) = 0.0f;
  reference.at<float>(40, 300) = 0.5f;  // too near: not a reference pixel
  ErrorImageOptions options;
  options.point_radius_px = 0;
  const cv::Mat image = RenderErrorImage(reference, mesh, cv::Mat(), DepthAccuracyOptions(), options, "test");
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.rows, kH + options.legend_height_px);
  ASSERT_EQ(image.cols, kW);
  EXPECT_EQ(image.at<cv::Vec3b>(10, 10), ErrorColour(0.0, options));
  EXPECT_EQ(image.at<cv::Vec3b>(10, 50), ErrorColour(options.max_error_m, options));
  EXPECT_EQ(image.at<cv::Vec3b>(10, 90), ErrorColour(1.0, options));
  EXPECT_NE(ErrorColour(0.0, options), ErrorColour(1.0, options));
  EXPECT_NE(ErrorColour(1.0, options), ErrorColour(2.0, options));
  EXPECT_EQ(image.at<cv::Vec3b>(40, 200), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(image.at<cv::Vec3b>(40, 300), cv::Vec3b(128, 128, 128));
  EXPECT_EQ(image.at<cv::Vec3b>(0, 0), cv::Vec3b(128, 128, 128));
  // The legend band holds the colour bar (its colours, not grey) and dark text.
  const cv::Mat band = image.rowRange(kH, image.rows);
  int coloured = 0, dark = 0;
  for (int y = 0; y < band.rows; ++y) {
    for (int x = 0; x < band.cols; ++x) {
      const cv::Vec3b c = band.at<cv::Vec3b>(y, x);
      coloured += (c[0] != c[1] || c[1] != c[2]) ? 1 : 0;
      dark += (c[0] < 80 && c[1] < 80 && c[2] < 80) ? 1 : 0;
    }
  }
  EXPECT_GT(coloured, 500);
  EXPECT_GT(dark, 100);
}

TEST(ErrorImage, SparsePointsAreSquaresLargeErrorsOnTopAndTheBackgroundIsGrey) {
  cv::Mat reference(20, 20, CV_32F, cv::Scalar(0.0f));
  cv::Mat mesh(20, 20, CV_32F, cv::Scalar(10.0f));
  reference.at<float>(10, 10) = 10.0f;  // 0 m
  reference.at<float>(10, 11) = 7.0f;   // 3 m: drawn last, over its neighbour's square
  cv::Mat background(20, 20, CV_8UC3, cv::Scalar(0, 0, 255));
  ErrorImageOptions options;  // radius 1
  const cv::Mat image = RenderErrorImage(reference, mesh, background, DepthAccuracyOptions(), options, "");
  EXPECT_EQ(image.at<cv::Vec3b>(10, 10), ErrorColour(3.0, options));
  EXPECT_EQ(image.at<cv::Vec3b>(9, 9), ErrorColour(0.0, options));
  EXPECT_EQ(image.at<cv::Vec3b>(10, 12), ErrorColour(3.0, options));
  const cv::Vec3b far = image.at<cv::Vec3b>(0, 0);
  EXPECT_EQ(far[0], far[1]);  // the red background turned grey
  EXPECT_EQ(far[1], far[2]);
}

// A grey background is dimmed to contrast 0.35 about mid-grey and quantised to steps of 8 grey levels (each
// pixel at the middle of its step), and the caller's image is left as it was.
TEST(ErrorImage, AGreyBackgroundIsDimmedToFewLevelsAndLeftUntouched) {
  cv::Mat reference(4, 256, CV_32F, cv::Scalar(0.0f));  // no reference pixel: all background
  cv::Mat mesh(4, 256, CV_32F, cv::Scalar(0.0f));
  cv::Mat background(4, 256, CV_8UC1);
  for (int x = 0; x < 256; ++x) background.col(x).setTo(x);
  const cv::Mat original = background.clone();
  const cv::Mat image =
      RenderErrorImage(reference, mesh, background, DepthAccuracyOptions(), ErrorImageOptions(), "");
  EXPECT_EQ(cv::norm(background, original, cv::NORM_INF), 0.0);
  for (int x = 0; x < 256; ++x) {
    const double dimmed = std::round(0.35 * x + 0.5 * 0.65 * 255.0);  // convertTo rounds; stays below 256
    const int expected = static_cast<int>(dimmed) / 8 * 8 + 4;
    const cv::Vec3b c = image.at<cv::Vec3b>(2, x);
    EXPECT_EQ(int(c[0]), expected) << "grey level " << x;
    EXPECT_EQ(c[0], c[1]);
    EXPECT_EQ(c[1], c[2]);
  }
}

TEST(ErrorImage, BadOptionsAreNamed) {
  ErrorImageOptions o;
  o.max_error_m = 0.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = ErrorImageOptions();
  o.tick_step_m = 0.01;
  EXPECT_THROW(o.Check(), InvalidOption);
}

}  // namespace
}  // namespace semap
