// A Strecha set streamed as frames: what each frame carries, the frame selection, labels and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "engine/core/check.h"
#include "io/frame_source.h"
#include "io/sfm/strecha.h"
#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

using test::ExpectReadError;
using test::WriteText;

constexpr int kWidth = 64;
constexpr int kHeight = 48;

// Three views on the world x axis at 0, 0.5 and 1.5 m, all looking along +z (R = I), f = 50 px; the images
// are uniform colours (the frames' content is not swept here).
std::filesystem::path WriteSet(const std::string& name, const std::string& first_k_row = "50 0 32") {
  const auto root = test::TempDir() / name;
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "images");
  const double x_m[] = {0.0, 0.5, 1.5};
  for (int i = 0; i < 3; ++i) {
    const std::string file = "000" + std::to_string(i) + ".png";
    cv::imwrite((root / "images" / file).string(),
                cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(10 + 40 * i, 100, 200)));
    WriteText(root / "gt_dense_cameras" / (file + ".camera"),
              (i == 0 ? first_k_row : std::string("50 0 32")) +
                  "\n0 50 24\n0 0 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + std::to_string(x_m[i]) + " 0 0\n" +
                  std::to_string(kWidth) + " " + std::to_string(kHeight) + "\n");
  }
  return root;
}

TEST(StrechaSource, EachFrameCarriesItsCameraAndItsNearestViews) {
  const auto root = WriteSet("strecha_source");
  EXPECT_EQ(DetectLayout(root), DatasetLayout::kStrecha);
  auto source = OpenFrameSource(root, FrameSourceOptions());
  EXPECT_EQ(source->layout(), DatasetLayout::kStrecha);
  ASSERT_EQ(source->size(), 3);
  // Frame: its neighbours, nearest first, and the distance to the nearest.
  const std::vector<std::vector<std::int64_t>> neighbours{{1, 2}, {0, 2}, {1, 0}};
  const double nearest_m[] = {0.5, 0.5, 1.0};
  for (std::int64_t id = 0; id < 3; ++id) {
    SCOPED_TRACE("frame " + std::to_string(id));
    const std::optional<Frame> f = source->Next();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->id, id);
    EXPECT_DOUBLE_EQ(f->timestamp_s, 0.1 * double(id));
    EXPECT_EQ(f->left.type(), CV_8UC3);
    EXPECT_EQ(f->left.size(), cv::Size(kWidth, kHeight));
    EXPECT_TRUE(f->right.empty());
    EXPECT_DOUBLE_EQ(f->calibration.fx_px, 50.0);
    EXPECT_DOUBLE_EQ(f->calibration.cx_px, 32.0);
    EXPECT_DOUBLE_EQ(f->calibration.cy_px, 24.0);
    EXPECT_NEAR(f->calibration.baseline_m, nearest_m[id], 1e-9);
    EXPECT_TRUE(f->calibration.IsValid());
    ASSERT_TRUE(f->world_from_cam.has_value());
    EXPECT_NEAR(f->world_from_cam->translation().x(), id == 2 ? 1.5 : 0.5 * double(id), 1e-9);
    ASSERT_EQ(f->neighbour_views.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
      const CalibratedView& n = f->neighbour_views[k];
      EXPECT_EQ(n.frame_id, neighbours[id][k]);
      EXPECT_EQ(n.image.type(), CV_8UC1);
      EXPECT_EQ(n.image.size(), cv::Size(kWidth, kHeight));
      EXPECT_DOUBLE_EQ(n.K(0, 0), 50.0);
    }
    EXPECT_TRUE(f->labels.empty());
  }
  EXPECT_FALSE(source->Next().has_value());
}

TEST(StrechaSource, SelectionNeighbourCountAndLabels) {
  const auto root = WriteSet("strecha_source_selection");
  std::filesystem::create_directories(root / "labels");
  cv::imwrite((root / "labels" / "0001.png").string(), cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(7)));
  FrameSourceOptions o;
  o.first_frame = 1;
  o.max_frames = 1;
  o.neighbour_views = 1;
  const SequenceInfo info = DescribeDataset(root, o);
  EXPECT_EQ(info.layout, DatasetLayout::kStrecha);
  EXPECT_EQ(info.num_frames, 1);
  EXPECT_EQ(info.num_frames_on_disk, 3);
  EXPECT_TRUE(info.has_poses);
  EXPECT_TRUE(info.has_labels);
  EXPECT_NEAR(info.calibration.baseline_m, 0.5, 1e-9);
  auto source = OpenFrameSource(root, o);
  const std::optional<Frame> f = source->Next();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->id, 1);
  ASSERT_EQ(f->neighbour_views.size(), 1u);
  EXPECT_EQ(f->neighbour_views[0].frame_id, 0);
  ASSERT_EQ(f->labels.size(), cv::Size(kWidth, kHeight));
  EXPECT_EQ(f->labels.at<std::uint8_t>(0, 0), 7);
  EXPECT_FALSE(source->Next().has_value());
}

TEST(StrechaSource, RefusesASkewAndBadInputNamingTheFile) {
  ExpectReadError(
      [&] { OpenFrameSource(WriteSet("strecha_source_skew", "50 0.5 32"), FrameSourceOptions()); },
      {"0000.png.camera", "skew"});
  const auto root = WriteSet("strecha_source_bad");
  WriteText(root / "gt_dense_cameras" / "0001.png.camera", "50 0 32\n0 50 24\n0 0 1\n0 0 0\n1 0 0\n0 2 0\n");
  ExpectReadError([&] { OpenFrameSource(root, FrameSourceOptions()); }, {"0001.png.camera", "line"});
  std::filesystem::remove(root / "gt_dense_cameras" / "0001.png.camera");
  ExpectReadError([&] { DescribeDataset(root, FrameSourceOptions()); }, {"0001.png.camera", "missing"});
  FrameSourceOptions none;
  none.neighbour_views = 0;
  EXPECT_THROW(OpenFrameSource(WriteSet("strecha_source_options"), none), InvalidOption);
}

TEST(StrechaSource, AnUnreadableImageCostsItsFrameOnly) {
  const auto root = WriteSet("strecha_source_unreadable");
  FrameSourceOptions o;
  o.neighbour_views = 1;  // frame 0's neighbour is 1, frame 1's 0, frame 2's 1
  auto source = OpenFrameSource(root, o);
  WriteText(root / "images" / "0000.png", "not a PNG");
  EXPECT_THROW(source->Next(), FrameError);
  std::filesystem::remove(root / "images" / "0000.png");  // a neighbour of frame 1: its frame fails too
  EXPECT_THROW(source->Next(), FrameError);
  const std::optional<Frame> f = source->Next();
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->id, 2);
}

}  // namespace
}  // namespace semap::io
