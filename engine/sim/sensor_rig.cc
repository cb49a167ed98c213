#include "engine/sim/sensor_rig.h"

namespace semap::sim {
namespace {

Pose3d MakePose(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  Pose3d p = Pose3d::Identity();
  p.linear() = r;
  p.translation() = t;
  return p;
}

}  // namespace

Pose3d SensorRig::velo_from_imu() const { return MakePose(imu_to_velo_R, imu_to_velo_T); }
Pose3d SensorRig::cam0_from_velo() const { return MakePose(velo_to_cam_R, velo_to_cam_T); }
Pose3d SensorRig::cam2_from_velo() const {
  return Pose3d(Eigen::Translation3d(cam2_offset_x_m, 0.0, 0.0)) * cam0_from_velo();
}
Pose3d SensorRig::cam2_from_imu() const { return cam2_from_velo() * velo_from_imu(); }
Pose3d SensorRig::cam2_from_cam3() const {
  return Pose3d(Eigen::Translation3d(calibration.baseline_m, 0.0, 0.0));
}

SensorRig SensorRig::KittiLike(const SynthOptions& o) {
  SensorRig rig;
  rig.calibration.fx_px = o.fx_px;
  rig.calibration.fy_px = o.fy_px;
  rig.calibration.cx_px = o.cx_px;
  rig.calibration.cy_px = o.cy_px;
  rig.calibration.baseline_m = o.baseline_m;
  rig.calibration.width_px = o.image_width_px;
  rig.calibration.height_px = o.image_height_px;
  // Velodyne axes (x fwd, y left, z up) to camera axes (x right, y down, z fwd).
  rig.velo_to_cam_R << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  rig.velo_to_cam_T = Eigen::Vector3d(0.0, -0.08, -0.27);
  rig.imu_to_velo_R.setIdentity();
  rig.imu_to_velo_T = Eigen::Vector3d(-0.81, 0.32, -0.80);
  rig.cam2_offset_x_m = 0.06;
  const double velo_height_m = 1.73;
  rig.imu_height_m = velo_height_m + rig.imu_to_velo_T.z();  // p_velo = p_imu + T: the IMU sits 0.8 m lower
  return rig;
}

}  // namespace semap::sim
