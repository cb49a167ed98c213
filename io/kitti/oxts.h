// KITTI raw OXTS (GPS/IMU) packets and their conversion to poses exactly as the KITTI devkit's
// convertOxtsToPose.m does it.
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io {

// One line of oxts/data/*.txt: 30 values in this order. NOTE: token-identical to the struct of the same
// name in io/synth/oxts.h (branch synth) so both branches can be merged; keep one copy when they meet.
struct OxtsPacket {
  double lat_deg = 0.0, lon_deg = 0.0, alt_m = 0.0;
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  double vn = 0.0, ve = 0.0, vf = 0.0, vl = 0.0, vu = 0.0;            // m/s: north, east, forward, left, up
  double ax = 0.0, ay = 0.0, az = 0.0, af = 0.0, al = 0.0, au = 0.0;  // m/s^2
  double wx = 0.0, wy = 0.0, wz = 0.0, wf = 0.0, wl = 0.0, wu = 0.0;  // rad/s
  double pos_accuracy = 0.0, vel_accuracy = 0.0;
  int navstat = 4, numsats = 10, posmode = 5, velmode = 5, orimode = 6;
};

// Number of values of an OXTS line.
inline constexpr int kOxtsValuesPerLine = 30;

// The 30 values of a packet in file order, and back (the last five are integers in KITTI files).
std::array<double, kOxtsValuesPerLine> OxtsValues(const OxtsPacket& packet);
OxtsPacket OxtsFromValues(const std::array<double, kOxtsValuesPerLine>& values);

// Parses one OXTS line; throws FileError(path) when it does not hold 30 finite numbers, the last five are
// not integers, or the latitude is outside (-90, 90).
OxtsPacket ParseOxtsLine(const std::string& line, const std::filesystem::path& path);
OxtsPacket ReadOxtsFile(const std::filesystem::path& path);
// Writes a packet as KITTI does (one line, space separated, full double precision).
void WriteOxtsFile(const std::filesystem::path& path, const OxtsPacket& packet);

// KITTI devkit: er = 6378137 (same definition as in io/synth/oxts.h).
inline constexpr double kOxtsEarthRadiusM = 6378137.0;

// The devkit's conversion. With er = 6378137 and scale = cos(lat_0·π/180) from the FIRST frame:
//   t = [scale·lon·π·er/180, scale·er·ln(tan((90+lat)·π/360)), alt],  R = Rz(yaw)·Ry(pitch)·Rx(roll),
//   imu pose_i = [R t];  world_from_imu_i = pose_0⁻¹ · pose_i  (world = IMU frame of the first frame).
// Immutable after construction; thread-safe.
class OxtsPoseConverter {
 public:
  explicit OxtsPoseConverter(const OxtsPacket& first);

  double mercator_scale() const { return scale_; }
  // The un-normalised pose [R t] of a packet (Mercator metres), with this converter's scale.
  Pose3d MercatorPose(const OxtsPacket& packet) const;
  // pose_0⁻¹ · pose_i.
  Pose3d WorldFromImu(const OxtsPacket& packet) const;

 private:
  double scale_;
  Pose3d first_from_mercator_;  // pose_0⁻¹
};

}  // namespace semap::io
