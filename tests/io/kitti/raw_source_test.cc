// The KITTI raw reader on a tiny sequence written by the test (images, Velodyne, OXTS, timestamps, labels).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "engine/core/check.h"
#include "io/frame_source.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;
using test::TinyRaw;
using test::WriteTinyRaw;

bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

// Expected world_from_cam2 of frame i: the IMU moves step·i north while heading north, i.e. along its own
// x axis (world = IMU frame of frame 0); cam2_from_imu by the calibration chain written by hand.
Pose3d ExpectedPose(const TinyRaw& t, int i) {
  const auto& g = t.truth;
  Pose3d rect = Pose3d::Identity();
  rect.linear() = Eigen::AngleAxisd(g.rect_angle_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Pose3d cam2_from_cam0 = Pose3d::Identity();
  cam2_from_cam0.translation().x() = g.cam2_offset_m;
  const Pose3d cam2_from_imu = cam2_from_cam0 * rect * g.cam0_from_velo * g.velo_from_imu;
  Pose3d world_from_imu = Pose3d::Identity();
  world_from_imu.translation().x() = g.step_north_m * i;
  return world_from_imu * cam2_from_imu.inverse();
}

TEST(KittiRawSource, ReadsTinySequenceBack) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  // The root, the date folder and the drive folder all open the same drive.
  for (const fs::path& path : {t.root, t.date, t.drive}) {
    EXPECT_EQ(DetectLayout(path), DatasetLayout::kKittiRaw) << path;
  }
  auto source = OpenFrameSource(t.root, {});
  ASSERT_EQ(source->layout(), DatasetLayout::kKittiRaw);
  ASSERT_EQ(source->size(), 4);
  EXPECT_EQ(source->class_map().scheme(), "cityscapes");
  const auto& g = t.truth;
  for (int i = 0; i < 4; ++i) {
    const std::optional<Frame> f = source->Next();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->id, i);
    EXPECT_NEAR(f->timestamp_s, i * g.frame_period_s, 1e-6);
    EXPECT_TRUE(SameImage(f->left, test::TinyImage(i, 32, 16, false)));
    EXPECT_TRUE(SameImage(f->right, test::TinyImage(i, 32, 16, true)));
    EXPECT_TRUE(SameImage(f->labels, test::TinyLabels(i, 32, 16)));
    EXPECT_DOUBLE_EQ(f->calibration.fx_px, g.fx_px);
    EXPECT_DOUBLE_EQ(f->calibration.fy_px, g.fy_px);
    EXPECT_DOUBLE_EQ(f->calibration.cx_px, g.cx_px);
    EXPECT_DOUBLE_EQ(f->calibration.cy_px, g.cy_px);
    EXPECT_NEAR(f->calibration.baseline_m, g.baseline_m, 1e-12);
    EXPECT_EQ(f->calibration.width_px, 32);
    EXPECT_EQ(f->calibration.height_px, 16);
    ASSERT_TRUE(f->velodyne.has_value());
    EXPECT_EQ(f->velodyne->points_velo, test::TinyScan(i));
    ASSERT_TRUE(f->world_from_cam.has_value());
    const Pose3d want = ExpectedPose(t, i);
    // Mercator: 1 m of latitude is 1 m up to second order (< 0.1 mm here).
    EXPECT_LT((f->world_from_cam->translation() - want.translation()).norm(), 1e-4) << "frame " << i;
    EXPECT_LT((f->world_from_cam->linear() - want.linear()).cwiseAbs().maxCoeff(), 1e-9) << "frame " << i;
  }
  EXPECT_FALSE(source->Next().has_value());
  EXPECT_FALSE(source->Next().has_value());
}

TEST(KittiRawSource, LoopsShiftEachPassPastThePreviousTrack) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const double period_s = t.truth.frame_period_s;
  FrameSourceOptions options;
  options.loops = 3;
  options.loop_gap_m = 10.0;
  auto source = OpenFrameSource(t.root, options);
  ASSERT_EQ(source->size(), 12);
  // The track runs 3 m along world x: each pass is moved 3 + 10 m further along x, and the 10 m jump between
  // passes takes as long as the first pass's mean speed (1 m per period) needs for it.
  const double pass_s = 3 * period_s + 10 * period_s;
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 4; ++i) {
      const auto f = source->Next();
      ASSERT_TRUE(f.has_value());
      EXPECT_EQ(f->id, 4 * k + i);
      // The track's length is 3 m up to the Mercator approximation (< 0.1 mm): the jump time to 1e-4 s.
      EXPECT_NEAR(f->timestamp_s, i * period_s + k * pass_s, 1e-4) << "pass " << k << " frame " << i;
      const Pose3d want = ExpectedPose(t, i);
      const Eigen::Vector3d shift(13.0 * k, 0, 0);
      EXPECT_LT((f->world_from_cam->translation() - want.translation() - shift).norm(), 1e-4);
      EXPECT_LT((f->world_from_cam->linear() - want.linear()).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_TRUE(SameImage(f->left, test::TinyImage(i, 32, 16, false)));
    }
  }
  EXPECT_FALSE(source->Next().has_value());
  // A frame that fails in a later pass is reported with its id in the looped stream and the pass.
  fs::remove(t.drive / "image_03/data/0000000001.png");
  source = OpenFrameSource(t.root, options);
  std::vector<std::string> errors;
  std::vector<std::int64_t> ids;
  for (int n = 0; n < 20; ++n) {
    try {
      auto f = source->Next();
      if (!f) break;
      ids.push_back(f->id);
    } catch (const FrameError& e) {
      errors.push_back(std::to_string(e.frame_id()) + "|" + e.what());
    }
  }
  EXPECT_EQ(ids, (std::vector<std::int64_t>{0, 2, 3, 4, 6, 7, 8, 10, 11}));
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[2].substr(0, errors[2].find('|')), "9");
  EXPECT_NE(errors[2].find("pass 3: frame 1:"), std::string::npos) << errors[2];
  options.loops = 0;
  EXPECT_THROW(OpenFrameSource(t.root, options), InvalidOption);
}

TEST(KittiRawSource, VelodyneCalibrationChain) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const SequenceInfo info = DescribeDataset(t.drive, {});
  ASSERT_TRUE(info.cam_from_velo.has_value());
  // cam2_from_velo = T(x = P_rect_02[0,3]/fx) · R_rect_00 · [R|T]: a velodyne point 10 m ahead.
  const Eigen::Vector3d p_velo(10, 0, 0);
  const Eigen::Vector3d p_cam0 = t.truth.cam0_from_velo * p_velo;  // (0.1, -0.08, 9.73)
  const double a = t.truth.rect_angle_rad;
  const Eigen::Vector3d p_rect(std::cos(a) * p_cam0.x() + std::sin(a) * p_cam0.z(), p_cam0.y(),
                               -std::sin(a) * p_cam0.x() + std::cos(a) * p_cam0.z());
  const Eigen::Vector3d want = p_rect + Eigen::Vector3d(t.truth.cam2_offset_m, 0, 0);
  EXPECT_LT((*info.cam_from_velo * p_velo - want).norm(), 1e-9);
  EXPECT_TRUE(info.has_poses);
  EXPECT_TRUE(info.has_velodyne);
  EXPECT_TRUE(info.has_timestamps);
  EXPECT_TRUE(info.has_labels);
  EXPECT_EQ(info.label_files.size(), 4u);
  EXPECT_EQ(info.num_frames, 4);
  EXPECT_TRUE(info.color);
}

TEST(KittiRawSource, SelectsFramesAndKeepsTheWorldOfFrameZero) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw", {.num_frames = 5});
  FrameSourceOptions o;
  o.first_frame = 2;
  o.max_frames = 2;
  o.load_velodyne = false;
  auto source = OpenFrameSource(t.drive, o);
  ASSERT_EQ(source->size(), 2);
  for (int i : {2, 3}) {
    const auto f = source->Next();
    ASSERT_TRUE(f);
    EXPECT_EQ(f->id, i);
    EXPECT_FALSE(f->velodyne.has_value());
    EXPECT_NEAR(f->timestamp_s, i * t.truth.frame_period_s, 1e-6);  // still since frame 0
    EXPECT_LT((f->world_from_cam->translation() - ExpectedPose(t, i).translation()).norm(), 1e-4);
  }
  EXPECT_FALSE(source->Next());
}

TEST(KittiRawSource, OptionalPartsAbsent) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw",
                                 {.velodyne = false, .oxts = false, .labels = false, .timestamps = false});
  auto source = OpenFrameSource(t.root, {});
  const auto f = source->Next();
  ASSERT_TRUE(f);
  EXPECT_FALSE(f->world_from_cam.has_value());
  EXPECT_FALSE(f->velodyne.has_value());
  EXPECT_TRUE(f->labels.empty());
  const auto f1 = source->Next();
  EXPECT_DOUBLE_EQ(f1->timestamp_s, 0.1);  // default_frame_period_s
}

// --- bad input: each frame-level problem throws FrameError naming the file; the stream goes on -----------

// Reads the whole source; returns the ids read and fills `errors` with the FrameError messages.
std::vector<std::int64_t> Drain(FrameSource& source, std::vector<std::string>* errors) {
  std::vector<std::int64_t> ids;
  for (int guard = 0; guard < 100; ++guard) {
    try {
      auto f = source.Next();
      if (!f) break;
      ids.push_back(f->id);
    } catch (const FrameError& e) {
      errors->push_back(std::to_string(e.frame_id()) + "|" + e.what());
    }
  }
  return ids;
}

void ExpectOneBadFrame(const fs::path& root, std::int64_t bad_id, const fs::path& bad_file,
                       const std::string& problem) {
  auto source = OpenFrameSource(root, {});
  std::vector<std::string> errors;
  const auto ids = Drain(*source, &errors);
  std::vector<std::int64_t> want;
  for (std::int64_t i = 0; i < source->size(); ++i) {
    if (i != bad_id) want.push_back(i);
  }
  EXPECT_EQ(ids, want);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].substr(0, errors[0].find('|')), std::to_string(bad_id));
  EXPECT_NE(errors[0].find(bad_file.string()), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find(problem), std::string::npos) << errors[0];
}

TEST(KittiRawBadInput, MissingRightImage) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path right = t.drive / "image_03/data/0000000001.png";
  fs::remove(right);
  ExpectOneBadFrame(t.root, 1, right, "right image not found");
}

TEST(KittiRawBadInput, TruncatedPng) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path left = t.drive / "image_02/data/0000000002.png";
  test::TruncateFile(left, fs::file_size(left) / 2);
  ExpectOneBadFrame(t.root, 2, left, "cannot decode left image");
}

TEST(KittiRawBadInput, CorruptPng) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path right = t.drive / "image_03/data/0000000003.png";
  std::string bytes = test::ReadTextFile(right);
  for (size_t i = 40; i < bytes.size() - 12; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  test::WriteTextFile(right, bytes);
  ExpectOneBadFrame(t.root, 3, right, "cannot decode right image");
  const fs::path junk = t.drive / "image_03/data/0000000000.png";
  test::WriteTextFile(junk, "this is not a png");
  auto source = OpenFrameSource(t.root, {});
  EXPECT_THROW(source->Next(), FrameError);
}

TEST(KittiRawBadInput, VelodyneSizeNotMultipleOf16) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path bin = t.drive / "velodyne_points/data/0000000000.bin";
  test::TruncateFile(bin, fs::file_size(bin) - 3);
  ExpectOneBadFrame(t.root, 0, bin, "not a multiple of 16");
}

TEST(KittiRawBadInput, LabelImageOfWrongSizeIsPassedOnForTheLabelStage) {
  // The label stage resizes it or refuses it as semantics.size_mismatch says (README, Faults): the reader
  // hands it over as it is.
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path label = t.drive / "semantic/data/0000000002.png";
  const cv::Mat written = test::TinyLabels(2, 31, 16);
  cv::imwrite(label.string(), written);
  auto source = OpenFrameSource(t.root, {});
  std::vector<std::string> errors;
  EXPECT_EQ(Drain(*source, &errors), (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_TRUE(errors.empty());
  FrameSourceOptions third;
  third.first_frame = 2;
  third.max_frames = 1;
  auto again = OpenFrameSource(t.root, third);
  const auto f = again->Next();
  ASSERT_TRUE(f);
  EXPECT_TRUE(SameImage(f->labels, written));
  EXPECT_EQ(f->left.size(), cv::Size(32, 16));
}

TEST(KittiRawBadInput, MissingLabelImageCostsNothingWhenLabelsAreNotLoaded) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  fs::remove(t.drive / "semantic/data/0000000001.png");
  FrameSourceOptions options;
  options.load_labels = false;  // semantics.source none or enet
  auto source = OpenFrameSource(t.root, options);
  std::vector<std::string> errors;
  EXPECT_EQ(Drain(*source, &errors), (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_TRUE(errors.empty());
}

TEST(KittiRawBadInput, EmptyVelodyneScanIsAMissingScan) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path bin = t.drive / "velodyne_points/data/0000000001.bin";
  test::TruncateFile(bin, 0);
  ExpectOneBadFrame(t.root, 1, bin, "Velodyne scan is empty");
}

TEST(KittiRawBadInput, FrameOfAnotherSizeThanTheCalibrationIsRefused) {
  // The calibration holds for the first image's size; a larger frame would be mapped with wrong intrinsics.
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path left = t.drive / "image_02/data/0000000002.png";
  cv::imwrite(left.string(), test::TinyImage(2, 64, 32, false));
  cv::imwrite((t.drive / "image_03/data/0000000002.png").string(), test::TinyImage(2, 64, 32, true));
  ExpectOneBadFrame(t.root, 2, left, "left image is 64x32 but the calibration is for 32x16");
}

TEST(KittiRawBadInput, MissingOrCorruptOxtsOfOneFrame) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path oxts = t.drive / "oxts/data/0000000001.txt";
  test::WriteTextFile(oxts, "49.0 8.4 nan\n");
  ExpectOneBadFrame(t.root, 1, oxts, "OXTS value 3 is not finite");
  fs::remove(oxts);
  ExpectOneBadFrame(t.root, 1, oxts, "OXTS file not found");
}

// Runs `fn`, expects a FileError naming `path` and containing `problem`.
void ExpectFileError(const std::function<void()>& fn, const fs::path& path, const std::string& problem) {
  try {
    fn();
    ADD_FAILURE() << "no FileError for " << path;
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
  }
}

TEST(KittiRawBadInput, CalibrationMissingKeyOrNaN) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path cam = t.date / "calib_cam_to_cam.txt";
  const std::string good = test::ReadTextFile(cam);
  // Missing key: drop the P_rect_03 line.
  std::string text = good;
  const auto at = text.find("P_rect_03");
  text.erase(at, text.find('\n', at) - at + 1);
  test::WriteTextFile(cam, text);
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "missing key 'P_rect_03'");
  // NaN in a value.
  text = good;
  text.replace(text.find("P_rect_02:") + 11, 3, "nan");
  test::WriteTextFile(cam, text);
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "key 'P_rect_02': value 1 is nan (not finite)");
  test::WriteTextFile(cam, good);
  // Velodyne calibration with a missing T.
  const fs::path velo = t.date / "calib_velo_to_cam.txt";
  test::WriteTextFile(velo, "R: 1 0 0 0 1 0 0 0 1\n");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, velo, "missing key 'T'");
  fs::remove(t.date / "calib_cam_to_cam.txt");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "calibration file not found");
}

TEST(KittiRawBadInput, ImplausibleIntrinsicsAreAnErrorNamingFileAndKey) {
  // Typos in P_rect_02 (cx = 1e9, cx = 6095593, cy = 1728540, a focal length of 1e12): an error at open,
  // before any frame, instead of an assertion, gigabytes or a nonsense mesh.
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path cam = t.date / "calib_cam_to_cam.txt";
  const std::string good = test::ReadTextFile(cam);
  // P_rect_02's values: fx 0 cx tx 0 fy cy 0 0 0 1 0.
  auto with = [&](int index, const std::string& value) {
    const auto line = good.find("P_rect_02:");
    std::istringstream in(good.substr(line + 10, good.find('\n', line) - line - 10));
    std::vector<std::string> v;
    for (std::string x; in >> x;) v.push_back(x);
    v.at(index) = value;
    std::string text = good.substr(0, line) + "P_rect_02:";
    for (const auto& x : v) text += " " + x;
    test::WriteTextFile(cam, text + good.substr(good.find('\n', line)));
  };
  with(2, "1e9");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam,
                  "key 'P_rect_02': principal point cx = 1e+09 px lies outside the 32x16 image");
  with(2, "6095593");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "principal point cx = 6095593 px");
  with(6, "1728540");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "principal point cy = 1728540 px");
  with(5, "1e12");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, cam, "key 'P_rect_02': focal length fy = 1e+12 px");
}

TEST(KittiRawBadInput, MissingVelodyneCalibrationIsNamedByEveryFrameThatNeedsAPose) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path velo = t.date / "calib_velo_to_cam.txt";
  fs::remove(velo);
  auto source = OpenFrameSource(t.root, {});
  std::vector<std::string> errors;
  EXPECT_TRUE(Drain(*source, &errors).empty());
  ASSERT_EQ(errors.size(), 4u);
  for (const auto& e : errors) {
    EXPECT_NE(e.find(velo.string() + ": calibration file not found"), std::string::npos) << e;
  }
}

TEST(KittiRawBadInput, TimestampsShorterThanFramesOrMalformed) {
  const TinyRaw t = WriteTinyRaw(test::TempDir() / "raw");
  const fs::path stamps = t.drive / "image_02/timestamps.txt";
  const std::string good = test::ReadTextFile(stamps);
  test::WriteTextFile(stamps, good.substr(0, good.find('\n') + 1));
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, stamps, "has 1 timestamps but frame 3 needs line 4");
  test::WriteTextFile(stamps, "2011-09-26 13:02:25.9\n2011-13-26 13:02:26.0\n");
  ExpectFileError([&] { OpenFrameSource(t.root, {}); }, stamps, "line 2");
}

TEST(KittiRawBadInput, MissingFolderAndAmbiguousRoot) {
  const fs::path dir = test::TempDir();
  const fs::path missing = dir / "does_not_exist";
  ExpectFileError([&] { OpenFrameSource(missing, {}); }, missing, "dataset folder not found");
  FrameSourceOptions raw;
  raw.layout = DatasetLayout::kKittiRaw;
  ExpectFileError([&] { OpenFrameSource(missing, raw); }, missing, "dataset folder not found");
  const TinyRaw t = WriteTinyRaw(dir / "raw");
  fs::copy(t.drive, t.date / "2011_09_26_drive_0002_sync", fs::copy_options::recursive);
  ExpectFileError([&] { OpenFrameSource(t.date, {}); }, t.date, "holds 2 KITTI raw drives");
  // A drive whose right-image folder is missing entirely.
  fs::remove_all(t.drive / "image_03");
  ExpectFileError([&] { OpenFrameSource(t.drive, {}); }, t.drive / "image_03/data",
                  "right image folder not found");
  const fs::path empty = dir / "empty";
  fs::create_directories(empty);
  ExpectFileError([&] { OpenFrameSource(empty, {}); }, empty, "cannot detect the dataset layout");
}

}  // namespace
}  // namespace semap::io
