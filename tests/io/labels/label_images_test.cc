#include "io/labels/label_images.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

std::string ErrorOf(const fs::path& path, cv::Size size) {
  try {
    ReadLabelImage(path, size);
  } catch (const FileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LabelImages, ReadsIdsExactly) {
  const fs::path path = test::TempDir() / "l.png";
  cv::Mat m(4, 6, CV_8UC1);
  for (int i = 0; i < 24; ++i) m.data[i] = static_cast<uchar>(i * 10);
  cv::imwrite(path.string(), m);
  const cv::Mat r = ReadLabelImage(path, {6, 4});
  EXPECT_EQ(cv::norm(r, m, cv::NORM_INF), 0);
  EXPECT_EQ(ReadLabelImage(path).size(), cv::Size(6, 4));
}

TEST(LabelImages, BadImages) {
  const fs::path dir = test::TempDir();
  cv::imwrite((dir / "l.png").string(), cv::Mat(4, 6, CV_8UC1, cv::Scalar(1)));
  EXPECT_EQ(ErrorOf(dir / "l.png", {6, 5}),
            (dir / "l.png").string() + ": label image is 6x4 but the left image is 6x5");
  cv::imwrite((dir / "rgb.png").string(), cv::Mat(4, 6, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_NE(ErrorOf(dir / "rgb.png", {}).find("must be 8-bit single channel"), std::string::npos);
  cv::imwrite((dir / "u16.png").string(), cv::Mat(4, 6, CV_16UC1, cv::Scalar(1)));
  EXPECT_NE(ErrorOf(dir / "u16.png", {}).find("must be 8-bit single channel"), std::string::npos);
  std::ofstream(dir / "junk.png") << "not a png";
  EXPECT_NE(ErrorOf(dir / "junk.png", {}).find("cannot decode label image"), std::string::npos);
  EXPECT_EQ(ErrorOf(dir / "none.png", {}), (dir / "none.png").string() + ": label image not found");
}

TEST(LabelImages, CompositionByRoleAndClass) {
  // 10 pixels: 4 road, 1 sidewalk (ground), 2 building (wall), 1 vegetation, 1 car, 1 sky.
  cv::Mat m = (cv::Mat_<uchar>(1, 10) << 1, 1, 1, 1, 2, 3, 3, 9, 14, 11);
  LabelHistogram h;
  h.Add(m);
  EXPECT_EQ(h.total, 10);
  const auto rows = SummariseByRole(h, ClassMap::Cityscapes());
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0].name, "ground");
  EXPECT_DOUBLE_EQ(rows[0].share, 0.5);
  EXPECT_DOUBLE_EQ(rows[1].share, 0.2);  // wall
  EXPECT_DOUBLE_EQ(rows[2].share, 0.1);  // vegetation
  EXPECT_DOUBLE_EQ(rows[3].share, 0.1);  // car
  EXPECT_DOUBLE_EQ(rows[4].share, 0.1);  // other (sky)
  const auto classes = SummariseByClass(h, ClassMap::Cityscapes());
  ASSERT_EQ(classes.size(), 6u);
  EXPECT_EQ(classes[0].name, "Road");
  EXPECT_DOUBLE_EQ(classes[0].share, 0.4);
  // Unknown ids are named by number.
  LabelHistogram h2;
  h2.Add(cv::Mat(2, 2, CV_8UC1, cv::Scalar(200)));
  EXPECT_EQ(SummariseByClass(h2, ClassMap::Cityscapes())[0].name, "id 200");
  EXPECT_DOUBLE_EQ(SummariseByRole(h2, ClassMap::Cityscapes())[4].share, 1.0);
}

}  // namespace
}  // namespace semap::io
