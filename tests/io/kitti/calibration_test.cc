#include "io/kitti/calibration.h"

#include <gtest/gtest.h>

#include <functional>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

void ExpectFileError(const std::function<void()>& fn, const fs::path& path, const std::string& problem) {
  try {
    fn();
    ADD_FAILURE() << "no FileError for " << path;
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
  }
}

constexpr const char* kOdometryCalib =
    "P0: 7.215377e+02 0 6.095593e+02 0 0 7.215377e+02 1.728540e+02 0 0 0 1 0\n"
    "P1: 7.215377e+02 0 6.095593e+02 -3.875744e+02 0 7.215377e+02 1.728540e+02 0 0 0 1 0\n"
    "P2: 7.215377e+02 0 6.095593e+02 4.485728e+01 0 7.215377e+02 1.728540e+02 2.163791e-01 0 0 1 "
    "2.745884e-03\n"
    "P3: 7.215377e+02 0 6.095593e+02 -3.395242e+02 0 7.215377e+02 1.728540e+02 2.199936e+00 0 0 1 "
    "2.729905e-03\n"
    "Tr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n";

TEST(KittiCalibration, OdometryGrayAndColourPairs) {
  const fs::path path = test::TempDir() / "calib.txt";
  test::WriteTextFile(path, kOdometryCalib);
  const OdometryCalibration gray = ReadOdometryCalibration(path, OdometryPair::kGray);
  EXPECT_DOUBLE_EQ(gray.stereo.fx_px, 721.5377);
  EXPECT_DOUBLE_EQ(gray.stereo.fy_px, 721.5377);
  EXPECT_DOUBLE_EQ(gray.stereo.cx_px, 609.5593);
  EXPECT_DOUBLE_EQ(gray.stereo.cy_px, 172.854);
  EXPECT_NEAR(gray.stereo.baseline_m, 387.5744 / 721.5377, 1e-12);  // 0.537150 m
  EXPECT_TRUE(gray.cam_from_cam0.isApprox(Pose3d::Identity()));
  ASSERT_TRUE(gray.cam_from_velo.has_value());
  EXPECT_LT((*gray.cam_from_velo * Eigen::Vector3d(10, 0, 0) - Eigen::Vector3d(0.1, 0.2, 10.3)).norm(),
            1e-12);

  const OdometryCalibration color = ReadOdometryCalibration(path, OdometryPair::kColor);
  EXPECT_NEAR(color.stereo.baseline_m, (44.85728 + 339.5242) / 721.5377, 1e-12);  // 0.532719 m
  EXPECT_NEAR(color.cam_from_cam0.translation().x(), 44.85728 / 721.5377, 1e-12);
  EXPECT_LT((*color.cam_from_velo * Eigen::Vector3d(10, 0, 0) -
             Eigen::Vector3d(0.1 + 44.85728 / 721.5377, 0.2, 10.3))
                .norm(),
            1e-12);
}

TEST(KittiCalibration, TrIsOptional) {
  const fs::path path = test::TempDir() / "calib.txt";
  std::string text = kOdometryCalib;
  text = text.substr(0, text.find("Tr:"));
  test::WriteTextFile(path, text);
  EXPECT_FALSE(ReadOdometryCalibration(path, OdometryPair::kGray).cam_from_velo.has_value());
}

TEST(KittiCalibration, RealStereo2015Calibration) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  const RawCalibration c = ReadRawCalibration(test::SharedDir() / "data/kitti_stereo2015_subset");
  EXPECT_DOUBLE_EQ(c.stereo.fx_px, 721.5377);
  EXPECT_NEAR(c.stereo.baseline_m, (44.85728 + 339.5242) / 721.5377, 1e-12);
  ASSERT_TRUE(c.cam2_from_velo.has_value());
  EXPECT_FALSE(c.cam2_from_imu.has_value());  // no calib_imu_to_velo.txt in the subset
  // cam2_from_velo = T(x = P_rect_02[0,3]/fx) · R_rect_00 · [R|T], with the numbers of the files.
  Eigen::Matrix3d r_velo, r_rect;
  r_velo << 7.533745e-03, -9.999714e-01, -6.166020e-04, 1.480249e-02, 7.280733e-04, -9.998902e-01,
      9.998621e-01, 7.523790e-03, 1.480755e-02;
  r_rect << 9.999239e-01, 9.837760e-03, -7.445048e-03, -9.869795e-03, 9.999421e-01, -4.278459e-03,
      7.402527e-03, 4.351614e-03, 9.999631e-01;
  const Eigen::Vector3d t_velo(-4.069766e-03, -7.631618e-02, -2.717806e-01);
  const Eigen::Vector3d p_velo(10, 2, -1);
  const Eigen::Vector3d want =
      r_rect * (r_velo * p_velo + t_velo) + Eigen::Vector3d(44.85728 / 721.5377, 0, 0);
  // The reader re-orthonormalises the 7-digit rotations: agreement to ~1e-6 m at 10 m.
  EXPECT_LT((*c.cam2_from_velo * p_velo - want).norm(), 1e-5);
}

TEST(KittiCalibration, BadFiles) {
  const fs::path dir = test::TempDir();
  const fs::path calib = dir / "calib.txt";
  test::WriteTextFile(calib, "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib, "missing key 'P1'");
  test::WriteTextFile(calib, "P0: 1 0 0 0 0 1 0 0 0 0 1\nP1: 1 0 0 -1 0 1 0 0 0 0 1 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib,
                  "key 'P0' has 11 values, expected 12");
  test::WriteTextFile(calib, "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 NaN 0 1 0 0 0 0 1 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib,
                  "key 'P1': value 4 is NaN (not finite)");
  test::WriteTextFile(calib, "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 one 0 1 0 0 0 0 1 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib,
                  "key 'P1': value 'one' is not a number");
  test::WriteTextFile(calib, "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 1 0 1 0 0 0 0 1 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib, "baseline");
  test::WriteTextFile(calib, "P0 1 0 0\n");
  ExpectFileError([&] { ReadOdometryCalibration(calib, OdometryPair::kGray); }, calib,
                  "line 1 is not 'key: values'");
  ExpectFileError([&] { ReadOdometryCalibration(dir / "none.txt", OdometryPair::kGray); }, dir / "none.txt",
                  "calibration file not found");
  const fs::path rigid = dir / "calib_velo_to_cam.txt";
  test::WriteTextFile(rigid, "R: 1 0 0 0 2 0 0 0 1\nT: 0 0 0\n");
  ExpectFileError([&] { ReadRigidTransform(rigid); }, rigid, "not a rotation matrix");
}

}  // namespace
}  // namespace semap::io
