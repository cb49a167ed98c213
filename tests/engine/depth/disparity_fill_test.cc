#include "engine/depth/internal/disparity_fill.h"

#include <gtest/gtest.h>

namespace semap::depth_internal {
namespace {

cv::Mat Row(std::initializer_list<float> values) {
  cv::Mat m(1, static_cast<int>(values.size()), CV_32F);
  int i = 0;
  for (float v : values) m.at<float>(0, i++) = v;
  return m;
}

std::vector<float> Values(const cv::Mat& m) { return std::vector<float>(m.begin<float>(), m.end<float>()); }

TEST(FillDisparity, SmallGapsTakeTheBackgroundDisparity) {
  cv::Mat d = Row({5, 0, 0, 9, 0, 0, 0, 0, 4, -1, NAN, 0});
  cv::Mat c;
  FillDisparity(/*max_gap_px=*/3, /*border_px=*/0, 0.5f, &d, &c);
  // Gap of 2 filled with min(5, 9); gap of 4 too long; trailing run has no right end: invalid (0).
  EXPECT_EQ(Values(d), (std::vector<float>{5, 5, 5, 9, 0, 0, 0, 0, 4, 0, 0, 0}));
  EXPECT_EQ(Values(c), (std::vector<float>{1, 0.5f, 0.5f, 1, 0, 0, 0, 0, 1, 0, 0, 0}));
}

TEST(FillDisparity, LeftBorderExtendsTheFirstValidPixelWithZeroConfidence) {
  cv::Mat d = Row({0, 0, 0, 7, 8, 0, 9});
  cv::Mat c;
  FillDisparity(/*max_gap_px=*/0, /*border_px=*/4, 0.5f, &d, &c);
  EXPECT_EQ(Values(d), (std::vector<float>{7, 7, 7, 7, 8, 0, 9}));
  EXPECT_EQ(Values(c), (std::vector<float>{0, 0, 0, 1, 1, 0, 1}));
}

TEST(FillDisparity, BorderBeyondTheBandAndEmptyRowsStayInvalid) {
  cv::Mat d = Row({0, 0, 0, 0, 0, 3});
  cv::Mat c;
  FillDisparity(2, /*border_px=*/3, 0.5f, &d, &c);
  EXPECT_EQ(Values(d), (std::vector<float>{0, 0, 0, 0, 0, 3}));
  cv::Mat empty = Row({0, 0, 0});
  FillDisparity(2, 3, 0.5f, &empty, &c);
  EXPECT_EQ(Values(empty), (std::vector<float>{0, 0, 0}));
  EXPECT_EQ(Values(c), (std::vector<float>{0, 0, 0}));
}

}  // namespace
}  // namespace semap::depth_internal
