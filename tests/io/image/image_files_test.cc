#include "io/image/image_files.h"

#include <gtest/gtest.h>

#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

TEST(KittiDisparityPng, RoundTripsAtOneTwoHundredFiftySixthPixel) {
  cv::Mat d = (cv::Mat_<float>(2, 3) << 0.0f, 12.5f, -3.0f, std::numeric_limits<float>::quiet_NaN(), 300.0f,
               1.0f / 256.0f);
  const auto path = test::TempDir() / "disp.png";
  WriteKittiDisparityPng(path, d);
  const cv::Mat raw = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  EXPECT_EQ(raw.at<std::uint16_t>(0, 1), 3200);   // 12.5 · 256
  EXPECT_EQ(raw.at<std::uint16_t>(0, 2), 0);      // negative → none
  EXPECT_EQ(raw.at<std::uint16_t>(1, 0), 0);      // NaN → none
  EXPECT_EQ(raw.at<std::uint16_t>(1, 1), 65535);  // 300 px clamped
  const cv::Mat back = ReadKittiDisparityPng(path);
  EXPECT_FLOAT_EQ(back.at<float>(0, 1), 12.5f);
  EXPECT_FLOAT_EQ(back.at<float>(1, 2), 1.0f / 256.0f);
  EXPECT_FLOAT_EQ(back.at<float>(0, 0), 0.0f);
}

TEST(KittiDisparityPng, ErrorsNameThePath) {
  const auto missing = test::TempDir() / "none" / "disp.png";
  try {
    WriteKittiDisparityPng(missing, cv::Mat(2, 2, CV_32F, cv::Scalar(1.0f)));
    ADD_FAILURE() << "no error";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("none"), std::string::npos);
  }
  EXPECT_THROW(ReadKittiDisparityPng(missing), FileError);
  EXPECT_THROW(WriteKittiDisparityPng(test::TempDir() / "x.png", cv::Mat(2, 2, CV_8U)), FileError);
  const auto eight_bit = test::TempDir() / "eight.png";
  WritePng(eight_bit, cv::Mat(2, 2, CV_8UC1, cv::Scalar(4)));
  EXPECT_THROW(ReadKittiDisparityPng(eight_bit), FileError);
}

TEST(FalseColourDisparity, InvalidPixelsAreBlackAndNearIsWarm) {
  cv::Mat d = (cv::Mat_<float>(1, 3) << 0.0f, 10.0f, 100.0f);
  const cv::Mat c = FalseColourDisparity(d);
  ASSERT_EQ(c.type(), CV_8UC3);
  EXPECT_EQ(c.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
  // TURBO: high values are red (R > B), low values blue-ish (B > R).
  EXPECT_GT(c.at<cv::Vec3b>(0, 2)[2], c.at<cv::Vec3b>(0, 2)[0]);
  EXPECT_GT(c.at<cv::Vec3b>(0, 1)[0], c.at<cv::Vec3b>(0, 1)[2]);
}

}  // namespace
}  // namespace semap::io
