// KITTI raw OXTS (GPS/IMU) packets and their conversion to poses exactly as the KITTI devkit's
// convertOxtsToPose.m does it.
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io {

// One OXTS line: 30 values in the devkit's order. The first six are named; the rest are kept as read.
struct OxtsPacket {
  // lat lon alt roll pitch yaw vn ve vf vl vu ax ay az af al au wx wy wz wf wl wu pos_accuracy vel_accuracy
  // navstat numsats posmode velmode orimode
  std::array<double, 30> values{};

  double lat_deg() const { return values[0]; }
  double lon_deg() const { return values[1]; }
  double alt_m() const { return values[2]; }
  double roll_rad() const { return values[3]; }
  double pitch_rad() const { return values[4]; }
  double yaw_rad() const { return values[5]; }  // heading, 0 = east, positive counter-clockwise
};

// Parses one OXTS line; throws FileError(path) when it does not hold 30 finite numbers or the latitude is
// outside (-90, 90).
OxtsPacket ParseOxtsLine(const std::string& line, const std::filesystem::path& path);
OxtsPacket ReadOxtsFile(const std::filesystem::path& path);
// Writes a packet as KITTI does (one line, space separated, full double precision).
void WriteOxtsFile(const std::filesystem::path& path, const OxtsPacket& packet);

// The devkit's Earth radius (m) for the Mercator projection.
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
