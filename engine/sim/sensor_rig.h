// The KITTI-like sensor rig of generated sequences: IMU/GPS, Velodyne and the rectified colour stereo pair.
#pragma once

#include <Eigen/Core>

#include "engine/core/calibration.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

// Mounting of the sensors on the vehicle, in KITTI's frames: IMU x forward / y left / z up, Velodyne the
// same axes, cameras x right / y down / z forward. R_rect_00 is the identity (the images are rendered
// rectified). Value type, thread-safe to read.
struct SensorRig {
  StereoCalibration
      calibration;  // of the left colour camera (KITTI cam 2); the right one (cam 3) at +baseline
  // calib_velo_to_cam: p_cam0 = R * p_velo + T.
  Eigen::Matrix3d velo_to_cam_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d velo_to_cam_T = Eigen::Vector3d::Zero();
  // calib_imu_to_velo: p_velo = R * p_imu + T.
  Eigen::Matrix3d imu_to_velo_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d imu_to_velo_T = Eigen::Vector3d::Zero();
  // P_rect_02[0,3] / fx: x offset of cam 2 from the rectified cam 0 (KITTI convention).
  double cam2_offset_x_m = 0.0;
  // Height of the IMU above the road when the vehicle is level.
  double imu_height_m = 0.0;

  Pose3d velo_from_imu() const;
  Pose3d cam0_from_velo() const;  // R_rect_00 (identity) * [R|T]_velo_to_cam
  Pose3d cam2_from_velo() const;  // T(x = cam2_offset_x_m) * cam0_from_velo
  Pose3d cam2_from_imu() const;
  // The right camera: cam3 = cam2 shifted by +baseline along x.
  Pose3d cam2_from_cam3() const;

  // KITTI 2011_09_26-like mounting (Velodyne 1.73 m above the road, cam 0 8 cm below it and 27 cm ahead of
  // it, IMU 0.8 m below and 0.81 m behind the Velodyne) with the intrinsics and baseline of `options`.
  static SensorRig KittiLike(const SynthOptions& options);
};

}  // namespace semap::sim
