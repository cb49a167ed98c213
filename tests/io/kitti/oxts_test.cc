// OXTS → pose against numbers worked out by hand from the devkit's formulas (convertOxtsToPose.m).
#include "io/kitti/oxts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

constexpr double kPi = std::numbers::pi;

OxtsPacket Packet(double lat, double lon, double alt, double roll, double pitch, double yaw) {
  OxtsPacket p;
  p.values[0] = lat;
  p.values[1] = lon;
  p.values[2] = alt;
  p.values[3] = roll;
  p.values[4] = pitch;
  p.values[5] = yaw;
  return p;
}

TEST(Oxts, MercatorOfTheFirstFrameByHand) {
  // lat 49°, lon 8.4°: scale = cos 49° = 0.65605902899; er·π/180 = 111319.49079 m/°.
  //   tx = 0.65605902899 · 8.4 · 111319.49079 = 613470.1191 m
  //   ty = 0.65605902899 · 6378137 · ln(tan(139°·π/360)) = 4116679.4732 m
  const OxtsPoseConverter c(Packet(49.0, 8.4, 100.0, 0, 0, 0));
  EXPECT_NEAR(c.mercator_scale(), 0.65605902899, 1e-10);
  const Pose3d p = c.MercatorPose(Packet(49.0, 8.4, 100.0, 0, 0, 0));
  EXPECT_NEAR(p.translation().x(), 613470.1191, 1e-3);
  EXPECT_NEAR(p.translation().y(), 4116679.4732, 1e-3);
  EXPECT_DOUBLE_EQ(p.translation().z(), 100.0);
  // World = IMU frame of the first frame.
  EXPECT_LT((c.WorldFromImu(Packet(49.0, 8.4, 100.0, 0, 0, 0)).matrix() - Eigen::Matrix4d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
}

TEST(Oxts, RotationIsRzRyRx) {
  const double r = 0.1, p = 0.2, y = 0.3;
  const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p), cy = std::cos(y),
               sy = std::sin(y);
  Eigen::Matrix3d want;  // Rz(y)·Ry(p)·Rx(r) multiplied out by hand
  want << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,      //
      -sp, cp * sr, cp * cr;
  const OxtsPoseConverter c(Packet(49.0, 8.4, 0, 0, 0, 0));
  EXPECT_LT((c.MercatorPose(Packet(49.0, 8.4, 0, r, p, y)).linear() - want).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(Oxts, TwoFramesTenMetresApartWithYaw) {
  // Frame 0 heads north (yaw = π/2): its IMU x axis points north, y west, z up.
  // Frame 1: 10 m further north (Δlat = 10/er rad = 8.983152841e-5°), 2 m higher, yaw π/2 + 0.1.
  //   Mercator Δy = scale·er·Δln tan = 10.000009 m (≈ 10: the scale cancels 1/cos lat to first order)
  //   → world_from_imu_1 = [Rz(0.1) | (10.000009, 0, 2)].
  // Frame 2: 10 m east of frame 0 (Δlon = 10/(er·cos 49°) rad = 1.369259845e-4°), same yaw as frame 0
  //   → Mercator Δx = scale·Δlon·π·er/180 = 10 m exactly → east is -y of frame 0: (0, -10, 0).
  const OxtsPoseConverter c(Packet(49.0, 8.4, 100.0, 0, 0, kPi / 2));
  const Pose3d p1 = c.WorldFromImu(Packet(49.0 + 8.983152841195215e-05, 8.4, 102.0, 0, 0, kPi / 2 + 0.1));
  EXPECT_NEAR(p1.translation().x(), 10.000009, 1e-6);
  EXPECT_NEAR(p1.translation().y(), 0.0, 1e-6);
  EXPECT_NEAR(p1.translation().z(), 2.0, 1e-9);
  Eigen::Matrix3d rz;
  rz << std::cos(0.1), -std::sin(0.1), 0, std::sin(0.1), std::cos(0.1), 0, 0, 0, 1;
  EXPECT_LT((p1.linear() - rz).cwiseAbs().maxCoeff(), 1e-12);

  const Pose3d p2 = c.WorldFromImu(Packet(49.0, 8.4 + 1.369259844654191e-04, 100.0, 0, 0, kPi / 2));
  EXPECT_NEAR(p2.translation().x(), 0.0, 1e-6);
  EXPECT_NEAR(p2.translation().y(), -10.0, 1e-6);
  EXPECT_NEAR(p2.translation().z(), 0.0, 1e-9);
  EXPECT_LT((p2.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Oxts, ScaleComesFromTheFirstFrame) {
  // Same two positions, converter anchored at a different latitude: translations scale with cos(lat_0).
  const OxtsPacket a = Packet(49.0, 8.4, 0, 0, 0, 0);
  const OxtsPacket b = Packet(49.0, 8.4 + 1.369259844654191e-04, 0, 0, 0, 0);
  const OxtsPoseConverter at_a(a);
  EXPECT_NEAR(at_a.WorldFromImu(b).translation().x(), 10.0, 1e-6);
  const OxtsPoseConverter at_equator(Packet(0.0, 8.4, 0, 0, 0, 0));
  EXPECT_NEAR((at_equator.MercatorPose(b).translation() - at_equator.MercatorPose(a).translation()).x(),
              10.0 / 0.65605902899, 1e-5);
}

TEST(Oxts, FileRoundTripAndBadLines) {
  const auto dir = test::TempDir();
  OxtsPacket p = Packet(49.011, 8.4237, 112.5, 0.01, -0.02, 1.5);
  for (int i = 6; i < 30; ++i) p.values[i] = i * 0.5;
  WriteOxtsFile(dir / "a.txt", p);
  EXPECT_EQ(ReadOxtsFile(dir / "a.txt").values, p.values);
  test::WriteTextFile(dir / "short.txt", "49 8 100 0 0 0\n");
  EXPECT_THROW(ReadOxtsFile(dir / "short.txt"), FileError);
  try {
    ReadOxtsFile(dir / "short.txt");
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("short.txt: OXTS line has 6 values, expected 30"), std::string::npos)
        << e.what();
  }
  test::WriteTextFile(dir / "word.txt", "49 8 abc\n");
  EXPECT_THROW(ReadOxtsFile(dir / "word.txt"), FileError);
  EXPECT_THROW(ReadOxtsFile(dir / "missing.txt"), FileError);
  std::string line = "95";
  for (int i = 1; i < 30; ++i) line += " 0";
  test::WriteTextFile(dir / "lat.txt", line + "\n");
  EXPECT_THROW(ReadOxtsFile(dir / "lat.txt"), FileError);
}

}  // namespace
}  // namespace semap::io
