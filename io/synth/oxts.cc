#include "io/synth/oxts.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace semap::io {

double OxtsMercatorScale(double first_latitude_deg) { return std::cos(first_latitude_deg * M_PI / 180.0); }

Pose3d OxtsToMercatorPose(const OxtsPacket& p, double scale) {
  Pose3d pose = Pose3d::Identity();
  pose.translation() = Eigen::Vector3d(
      scale * p.lon_deg * M_PI * kOxtsEarthRadiusM / 180.0,
      scale * kOxtsEarthRadiusM * std::log(std::tan((90.0 + p.lat_deg) * M_PI / 360.0)), p.alt_m);
  pose.linear() = (Eigen::AngleAxisd(p.yaw_rad, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(p.pitch_rad, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(p.roll_rad, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return pose;
}

OxtsPacket OxtsFromMercatorPose(const Pose3d& pose, double scale) {
  OxtsPacket p;
  const Eigen::Vector3d t = pose.translation();
  p.lon_deg = t.x() * 180.0 / (M_PI * kOxtsEarthRadiusM * scale);
  p.lat_deg = 360.0 / M_PI * std::atan(std::exp(t.y() / (kOxtsEarthRadiusM * scale))) - 90.0;
  p.alt_m = t.z();
  const Eigen::Matrix3d r = pose.linear();
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch), R(2,1) = cos(pitch) sin(roll),
  // R(2,2) = cos(pitch) cos(roll), R(1,0) = sin(yaw) cos(pitch), R(0,0) = cos(yaw) cos(pitch).
  p.pitch_rad = std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2)));
  p.roll_rad = std::atan2(r(2, 1), r(2, 2));
  p.yaw_rad = std::atan2(r(1, 0), r(0, 0));
  return p;
}

std::string FormatOxtsLine(const OxtsPacket& p) {
  // 17 significant digits: doubles round-trip exactly.
  const double v[25] = {p.lat_deg, p.lon_deg, p.alt_m,        p.roll_rad,    p.pitch_rad, p.yaw_rad, p.vn,
                        p.ve,      p.vf,      p.vl,           p.vu,          p.ax,        p.ay,      p.az,
                        p.af,      p.al,      p.au,           p.wx,          p.wy,        p.wz,      p.wf,
                        p.wl,      p.wu,      p.pos_accuracy, p.vel_accuracy};
  std::string out;
  char buf[64];
  for (double x : v) {
    std::snprintf(buf, sizeof(buf), "%.17g ", x);
    out += buf;
  }
  std::snprintf(buf, sizeof(buf), "%d %d %d %d %d", p.navstat, p.numsats, p.posmode, p.velmode, p.orimode);
  return out + buf;
}

OxtsPacket ParseOxtsLine(const std::string& line) {
  std::istringstream is(line);
  std::vector<double> v;
  double x;
  while (is >> x) v.push_back(x);
  if (!is.eof() || v.size() != 30) {
    throw std::runtime_error("OXTS line must have 30 numbers (got " + std::to_string(v.size()) + ")");
  }
  OxtsPacket p;
  double* fields[25] = {&p.lat_deg, &p.lon_deg, &p.alt_m, &p.roll_rad,     &p.pitch_rad,
                        &p.yaw_rad, &p.vn,      &p.ve,    &p.vf,           &p.vl,
                        &p.vu,      &p.ax,      &p.ay,    &p.az,           &p.af,
                        &p.al,      &p.au,      &p.wx,    &p.wy,           &p.wz,
                        &p.wf,      &p.wl,      &p.wu,    &p.pos_accuracy, &p.vel_accuracy};
  for (int k = 0; k < 25; ++k) *fields[k] = v[k];
  p.navstat = static_cast<int>(v[25]);
  p.numsats = static_cast<int>(v[26]);
  p.posmode = static_cast<int>(v[27]);
  p.velmode = static_cast<int>(v[28]);
  p.orimode = static_cast<int>(v[29]);
  return p;
}

}  // namespace semap::io
