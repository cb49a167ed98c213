#include "io/synth/oxts.h"

#include <cmath>

namespace semap::io {

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

}  // namespace semap::io
