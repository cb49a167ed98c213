// The KITTI odometry reader: the real sequence 03 in ../shared and small sequences written by the test.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "io/frame_source.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// Line i of a poses file as a 3×4 matrix, parsed independently of the reader.
Eigen::Matrix<double, 3, 4> PoseLine(const fs::path& path, int i) {
  std::ifstream in(path);
  std::string line;
  for (int k = 0; k <= i; ++k) std::getline(in, line);
  std::istringstream is(line);
  Eigen::Matrix<double, 3, 4> m;
  for (int k = 0; k < 12; ++k) is >> m(k / 4, k % 4);
  return m;
}

TEST(KittiOdometrySource, RealSequence03) {
  SEMAP_REQUIRE_SHARED("data/kitti_odometry_03");
  const fs::path root = test::SharedDir() / "data/kitti_odometry_03";
  const fs::path poses_txt = root / "poses/03.txt";
  for (const fs::path& path : {root, root / "sequences/03"}) {
    auto source = OpenFrameSource(path, {});
    ASSERT_EQ(source->layout(), DatasetLayout::kKittiOdometry);
    ASSERT_EQ(source->size(), 5);
    for (int i = 0; i < 5; ++i) {
      const auto f = source->Next();
      ASSERT_TRUE(f);
      EXPECT_EQ(f->id, i);
      EXPECT_EQ(f->left.type(), CV_8UC1);
      EXPECT_EQ(f->right.size(), f->left.size());
      EXPECT_EQ(f->calibration.width_px, 1242);
      EXPECT_EQ(f->calibration.height_px, 375);
      EXPECT_DOUBLE_EQ(f->calibration.fx_px, 721.5377);
      EXPECT_NEAR(f->calibration.baseline_m, 0.5371506, 1e-6);
      EXPECT_NEAR(f->timestamp_s, 0.1 * i, 1e-12);  // no times.txt: 10 Hz
      ASSERT_TRUE(f->world_from_cam);
      const Eigen::Matrix<double, 3, 4> want = PoseLine(poses_txt, i);
      EXPECT_EQ(f->world_from_cam->matrix().topRows<3>(), want) << "frame " << i;
      EXPECT_FALSE(f->velodyne);
      EXPECT_TRUE(f->labels.empty());
    }
    EXPECT_FALSE(source->Next());
  }
}

// A 3-frame colour odometry sequence with poses, written by the test.
struct TinyOdometry {
  fs::path root, seq;
};

TinyOdometry WriteTinyOdometry(const fs::path& root, int frames, int pose_lines) {
  TinyOdometry t{root, root / "sequences" / "07"};
  for (const char* d : {"image_2", "image_3"}) fs::create_directories(t.seq / d);
  fs::create_directories(root / "poses");
  test::WriteTextFile(t.seq / "calib.txt",
                      "P0: 100 0 16 0 0 100 8 0 0 0 1 0\nP1: 100 0 16 -54 0 100 8 0 0 0 1 0\n"
                      "P2: 100 0 16 6 0 100 8 0 0 0 1 0\nP3: 100 0 16 -48 0 100 8 0 0 0 1 0\n");
  std::ofstream poses(root / "poses" / "07.txt");
  for (int i = 0; i < pose_lines; ++i) poses << "1 0 0 0 0 1 0 0 0 0 1 " << 1.5 * i << "\n";
  std::ofstream times(t.seq / "times.txt");
  for (int i = 0; i < frames; ++i) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", i);
    cv::imwrite((t.seq / "image_2" / name).string(), test::TinyImage(i, 32, 16, false));
    cv::imwrite((t.seq / "image_3" / name).string(), test::TinyImage(i, 32, 16, true));
    times << 100.0 + 0.25 * i << "\n";
  }
  return t;
}

TEST(KittiOdometrySource, ColourPairPoseIsShiftedToCam2) {
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 3, 3);
  auto source = OpenFrameSource(t.root, {});
  ASSERT_EQ(source->size(), 3);
  for (int i = 0; i < 3; ++i) {
    const auto f = source->Next();
    ASSERT_TRUE(f);
    EXPECT_EQ(f->left.type(), CV_8UC3);
    EXPECT_NEAR(f->calibration.baseline_m, 0.54, 1e-12);
    EXPECT_DOUBLE_EQ(f->timestamp_s, 0.25 * i);
    // world_from_cam2 = world_from_cam0 · T(x = -P2[0,3]/fx) = translation (-0.06, 0, 1.5 i).
    EXPECT_LT((f->world_from_cam->translation() - Eigen::Vector3d(-0.06, 0, 1.5 * i)).norm(), 1e-12);
  }
}

TEST(KittiOdometrySource, GrayPairOnRequest) {
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 2, 2);
  FrameSourceOptions o;
  o.odometry_pair = CameraPair::kGray;
  // No image_0 in this sequence: a clear error naming the folder.
  try {
    OpenFrameSource(t.root, o);
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), t.seq / "image_0");
  }
}

TEST(KittiOdometryBadInput, NonFinitePoseIsAnErrorAtOpenNamingFileAndLine) {
  // The poses are read when the sequence is opened: a bad line ends the run before any frame (README,
  // Faults).
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 3, 3);
  test::WriteTextFile(t.root / "poses" / "07.txt",
                      "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 nan 0 1 0 0 0 0 1 1.5\n1 0 0 0 0 1 0 0 0 0 1 3\n");
  try {
    OpenFrameSource(t.root, {});
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), (t.root / "poses" / "07.txt").string() +
                                         ": line 2 is not 12 finite numbers (3×4 row-major pose)");
  }
}

TEST(KittiOdometryBadInput, PosesFileShorterThanFrames) {
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 3, 2);
  try {
    OpenFrameSource(t.root, {});
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()),
              (t.root / "poses" / "07.txt").string() + ": has 2 poses but 3 frames need one each");
  }
  // Reading only the frames the file covers works.
  FrameSourceOptions o;
  o.max_frames = 2;
  EXPECT_EQ(OpenFrameSource(t.root, o)->size(), 2);
}

TEST(KittiOdometryBadInput, MissingRightImageIsSkipped) {
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 3, 3);
  fs::remove(t.seq / "image_3" / "000000.png");
  auto source = OpenFrameSource(t.seq, {});
  try {
    source->Next();
    FAIL() << "no error";
  } catch (const FrameError& e) {
    EXPECT_EQ(e.frame_id(), 0);
    EXPECT_NE(
        std::string(e.what()).find((t.seq / "image_3" / "000000.png").string() + ": right image not found"),
        std::string::npos)
        << e.what();
  }
  EXPECT_EQ(source->Next()->id, 1);
  EXPECT_EQ(source->Next()->id, 2);
  EXPECT_FALSE(source->Next());
}

TEST(KittiOdometryBadInput, RightImageOfAnotherSize) {
  const TinyOdometry t = WriteTinyOdometry(test::TempDir(), 2, 2);
  cv::imwrite((t.seq / "image_3" / "000001.png").string(), test::TinyImage(1, 30, 16, true));
  auto source = OpenFrameSource(t.seq, {});
  EXPECT_TRUE(source->Next());
  EXPECT_THROW(source->Next(), FrameError);
  EXPECT_FALSE(source->Next());
}

}  // namespace
}  // namespace semap::io
