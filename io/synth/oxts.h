// KITTI OXTS packets (GPS/IMU) and the devkit's conversion to poses (convertOxtsToPose.m), both ways.
#pragma once

#include <string>

#include "engine/core/calibration.h"

namespace semap::io {

// One line of oxts/data/*.txt: 30 values in this order.
struct OxtsPacket {
  double lat_deg = 0.0, lon_deg = 0.0, alt_m = 0.0;
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  double vn = 0.0, ve = 0.0, vf = 0.0, vl = 0.0, vu = 0.0;            // m/s: north, east, forward, left, up
  double ax = 0.0, ay = 0.0, az = 0.0, af = 0.0, al = 0.0, au = 0.0;  // m/s^2
  double wx = 0.0, wy = 0.0, wz = 0.0, wf = 0.0, wl = 0.0, wu = 0.0;  // rad/s
  double pos_accuracy = 0.0, vel_accuracy = 0.0;
  int navstat = 4, numsats = 10, posmode = 5, velmode = 5, orimode = 6;
};

// KITTI devkit: er = 6378137, scale = cos(lat_0 * pi / 180) of the FIRST frame.
inline constexpr double kOxtsEarthRadiusM = 6378137.0;
double OxtsMercatorScale(double first_latitude_deg);

// Forward (devkit): t = [scale*lon*pi*er/180, scale*er*ln(tan((90+lat)*pi/360)), alt],
// R = Rz(yaw) * Ry(pitch) * Rx(roll). The result is the un-normalised IMU pose (mercator_from_imu).
Pose3d OxtsToMercatorPose(const OxtsPacket& packet, double scale);

// Inverse of OxtsToMercatorPose for the position and orientation fields (the other fields are left 0):
// lon = x*180/(pi*er*scale), lat = 360/pi*atan(exp(y/(er*scale))) - 90, alt = z; roll, pitch, yaw from R.
// Requires |pitch| < 90 degrees.
OxtsPacket OxtsFromMercatorPose(const Pose3d& mercator_from_imu, double scale);

// The 30 space-separated values of an OXTS line (enough digits for sub-millimetre round trips).
std::string FormatOxtsLine(const OxtsPacket& packet);
// Parses a line written by FormatOxtsLine or by KITTI; throws std::runtime_error on a malformed line.
OxtsPacket ParseOxtsLine(const std::string& line);

}  // namespace semap::io
