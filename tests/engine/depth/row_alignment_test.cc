// FitRowOffsets and AlignRows against a pair whose misalignment is known: a textured left image, its right
// image shifted by a constant disparity and moved vertically by a chosen quadratic field.
#include "engine/depth/row_alignment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "engine/depth/stereo_depth.h"

namespace semap {
namespace {

constexpr int kWidthPx = 640;
constexpr int kHeightPx = 240;
constexpr float kDisparityPx = 12.0f;

// Random blobs, blurred: corners everywhere, as a textured street.
cv::Mat Texture() {
  cv::Mat noise(kHeightPx, kWidthPx, CV_8UC1);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat smooth;
  cv::GaussianBlur(noise, smooth, cv::Size(0, 0), 1.5);
  cv::normalize(smooth, smooth, 0, 255, cv::NORM_MINMAX);
  return smooth;
}

// The right image of `left`: content at left (u, v) appears at (u − d, v + offsets.At(u, v)).
cv::Mat RightImage(const cv::Mat& left, const RowOffsets& offsets) {
  cv::Mat map_x(left.size(), CV_32FC1), map_y(left.size(), CV_32FC1);
  for (int v = 0; v < left.rows; ++v) {
    for (int u = 0; u < left.cols; ++u) {
      // Inverse of the forward move, to first order (the offsets vary slowly).
      map_x.at<float>(v, u) = u + kDisparityPx;
      map_y.at<float>(v, u) = static_cast<float>(v - offsets.At(u + kDisparityPx, v));
    }
  }
  cv::Mat right;
  cv::remap(left, right, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return right;
}

RowOffsets Misalignment() {
  RowOffsets m;
  m.image_size = cv::Size(kWidthPx, kHeightPx);
  m.coefficients_px = {0.4, -1.0, 0.5, 6.0, 1.0, 2.0};  // up to ~1 px at the corners, as KITTI's turn
  return m;
}

TEST(RowAlignment, FitRecoversAKnownMisalignment) {
  const cv::Mat left = Texture();
  const RowOffsets truth = Misalignment();
  const auto fit = FitRowOffsets(left, RightImage(left, truth));
  ASSERT_TRUE(fit.has_value());
  EXPECT_GE(fit->matches, 1000);
  double worst = 0.0, largest = 0.0;
  for (int v = 0; v < kHeightPx; v += 8) {
    for (int u = 0; u < kWidthPx; u += 8) {
      worst = std::max(worst, std::abs(fit->At(u, v) - truth.At(u, v)));
      largest = std::max(largest, std::abs(truth.At(u, v)));
    }
  }
  EXPECT_GT(largest, 0.8);
  EXPECT_LT(worst, 0.1) << "the fitted field departs from the true one";
}

TEST(RowAlignment, AlignedRowsLeaveNoMisalignment) {
  const cv::Mat left = Texture();
  const cv::Mat right = RightImage(left, Misalignment());
  const auto fit = FitRowOffsets(left, right);
  ASSERT_TRUE(fit.has_value());
  const auto again = FitRowOffsets(left, AlignRows(right, *fit));
  ASSERT_TRUE(again.has_value());
  EXPECT_LT(again->max_abs_px, 0.1);
}

TEST(RowAlignment, NoTextureNoFit) {
  const cv::Mat blank(kHeightPx, kWidthPx, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(FitRowOffsets(blank, blank).has_value());
  EXPECT_THROW(FitRowOffsets(blank, cv::Mat(kHeightPx, kWidthPx, CV_8UC3)), std::invalid_argument);
}

// SGBM on the misaligned pair: lining the rows up gives more pixels at the true disparity; a pair already
// aligned is not resampled (the same disparity, bit for bit).
TEST(RowAlignment, StereoDepthMatchesBetterWithTheRowsLinedUp) {
  const cv::Mat left = Texture();
  const cv::Mat right = RightImage(left, Misalignment());
  DepthOptions on, off;
  on.num_disparities = off.num_disparities = 32;
  off.align_rows = false;
  // Mean |disparity error| of the matched pixels right of the band the right camera cannot see.
  const auto mean_error = [&](const DisparityResult& r) {
    const cv::Rect seen(2 * on.num_disparities, 0, kWidthPx - 2 * on.num_disparities, kHeightPx);
    const cv::Mat d = r.disparity_px(seen);
    return cv::mean(cv::abs(d - kDisparityPx), d > 0.0f)[0];
  };
  const DisparityResult aligned = StereoDepth(on).Compute(left, right);
  const DisparityResult raw = StereoDepth(off).Compute(left, right);
  EXPECT_GT(aligned.rows_aligned_px, 0.8);
  EXPECT_EQ(raw.rows_aligned_px, 0.0);
  EXPECT_LT(mean_error(aligned), 0.8 * mean_error(raw))
      << "aligned " << mean_error(aligned) << " px, raw " << mean_error(raw) << " px";

  RowOffsets none;
  none.image_size = left.size();
  const cv::Mat rectified = RightImage(left, none);
  const cv::Mat a = StereoDepth(on).Compute(left, rectified).disparity_px;
  const cv::Mat b = StereoDepth(off).Compute(left, rectified).disparity_px;
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  // Offsets measured elsewhere (a reader) are used as given: "nothing to correct" leaves the pair alone.
  EXPECT_EQ(StereoDepth(on).Compute(left, right, &none).rows_aligned_px, 0.0);
}

}  // namespace
}  // namespace semap
