// Layout detection and DescribeDataset on the three layouts.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "engine/core/check.h"
#include "io/frame_source.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

TEST(Dataset, DescribesRealOdometry) {
  SEMAP_REQUIRE_SHARED("data/kitti_odometry_03");
  const SequenceInfo info = DescribeDataset(test::SharedDir() / "data/kitti_odometry_03", {});
  EXPECT_EQ(info.layout, DatasetLayout::kKittiOdometry);
  EXPECT_EQ(info.num_frames, 5);
  EXPECT_EQ(info.first_frame_id, 0);
  EXPECT_EQ(info.last_frame_id, 4);
  EXPECT_FALSE(info.color);
  EXPECT_EQ(info.calibration.width_px, 1242);
  EXPECT_EQ(info.calibration.height_px, 375);
  EXPECT_TRUE(info.calibration.IsValid());
  EXPECT_TRUE(info.has_poses);
  EXPECT_FALSE(info.has_velodyne);
  EXPECT_FALSE(info.has_labels);
  EXPECT_FALSE(info.has_timestamps);
  EXPECT_EQ(info.root.filename(), "03");
}

TEST(Dataset, DescribesRealStereo2015) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  const SequenceInfo info = DescribeDataset(test::SharedDir() / "data/kitti_stereo2015_subset", {});
  EXPECT_EQ(info.layout, DatasetLayout::kKittiStereo2015);
  EXPECT_EQ(info.num_frames, 20);
  EXPECT_EQ(info.first_frame_id, 2);
  EXPECT_EQ(info.last_frame_id, 144);
  EXPECT_TRUE(info.color);
  EXPECT_TRUE(info.has_velodyne);
  EXPECT_TRUE(info.cam_from_velo.has_value());
}

TEST(Dataset, LabelsFolderAndClassMapOptions) {
  const fs::path dir = test::TempDir();
  const auto t = test::WriteTinyRaw(dir / "raw", {.labels = false});
  FrameSourceOptions o;
  o.labels_dir = (dir / "nowhere").string();
  try {
    DescribeDataset(t.root, o);
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "nowhere").string() + ": labels folder not found");
  }
  // Labels in a folder of the user's choice, same stems as the images.
  fs::create_directories(dir / "labels");
  cv::imwrite((dir / "labels" / "0000000001.png").string(), test::TinyLabels(1, 32, 16));
  o.labels_dir = (dir / "labels").string();
  const SequenceInfo info = DescribeDataset(t.root, o);
  EXPECT_TRUE(info.has_labels);
  ASSERT_EQ(info.label_files.size(), 1u);
  EXPECT_EQ(info.label_files[0], dir / "labels" / "0000000001.png");
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_NE(info.notes[0].find("3 selected frame(s) have no label image"), std::string::npos);
  o.class_map = (dir / "no_map.yaml").string();
  EXPECT_THROW(DescribeDataset(t.root, o), FileError);
}

TEST(Dataset, BadPaths) {
  const fs::path dir = test::TempDir();
  EXPECT_THROW(DetectLayout(dir / "missing"), FileError);
  test::WriteTextFile(dir / "file.txt", "x");
  try {
    DetectLayout(dir / "file.txt");
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("not a folder"), std::string::npos);
  }
  FrameSourceOptions bad;
  bad.first_frame = -1;
  EXPECT_THROW(OpenFrameSource(dir, bad), InvalidOption);
}

}  // namespace
}  // namespace semap::io
