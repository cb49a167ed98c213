// The inverse of the KITTI devkit's OXTS → pose conversion (io/kitti/oxts.h has the packet, the file format
// and the forward conversion): what the generator writes so that a KITTI reader recovers its trajectory.
#pragma once

#include "engine/core/calibration.h"
#include "io/kitti/oxts.h"

namespace semap::io {

// The packet whose devkit pose, with Mercator `scale` (cos of the first frame's latitude), is
// `mercator_from_imu`: lon/lat from the Mercator x/y, altitude from z, roll/pitch/yaw from R = Rz·Ry·Rx.
// Velocities, accelerations and rates are left zero; the status fields get plausible values.
OxtsPacket OxtsFromMercatorPose(const Pose3d& mercator_from_imu, double scale);

}  // namespace semap::io
