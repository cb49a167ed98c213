// A whole generated sequence: trajectory, world, sensors; renders any frame on demand.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "engine/core/class_map.h"
#include "engine/sim/bvh.h"
#include "engine/sim/camera_renderer.h"
#include "engine/sim/lidar_scanner.h"
#include "engine/sim/scene.h"
#include "engine/sim/sensor_rig.h"
#include "engine/sim/synth_options.h"
#include "engine/sim/trajectory.h"

namespace semap::sim {

struct SyntheticFrame {
  int index = 0;
  double timestamp_s = 0.0;
  CameraImage left;   // KITTI cam 2 (image_02)
  CameraImage right;  // KITTI cam 3 (image_03)
  LidarScan scan;     // in the Velodyne frame
};

// Owns the trajectory, the scene and its BVH. Immutable after construction: RenderFrame() is const,
// thread-safe and deterministic (a frame depends only on the options and its index), so frames can be
// rendered in parallel in any order.
class SyntheticSequence {
 public:
  explicit SyntheticSequence(const SynthOptions& options);
  ~SyntheticSequence();
  SyntheticSequence(const SyntheticSequence&) = delete;
  SyntheticSequence& operator=(const SyntheticSequence&) = delete;

  const SynthOptions& options() const { return options_; }
  const SensorRig& rig() const { return rig_; }
  const Trajectory& trajectory() const { return *trajectory_; }
  const Scene& scene() const { return *scene_; }
  const TriangleBvh& bvh() const { return *bvh_; }
  int num_frames() const { return trajectory_->num_frames(); }

  // Sensor poses in the scene frame.
  Pose3d scene_from_imu(int frame) const { return trajectory_->scene_from_imu(frame); }
  Pose3d scene_from_velo(int frame) const;
  Pose3d scene_from_cam2(int frame) const;
  Pose3d scene_from_cam3(int frame) const;
  // The world frame of the written sequence (KITTI devkit convention): the IMU frame of frame 0.
  Pose3d world_from_scene() const { return scene_from_imu(0).inverse(); }
  // Ground truth left camera pose in that world frame.
  Pose3d world_from_cam2(int frame) const { return world_from_scene() * scene_from_cam2(frame); }

  // Exposure gain of the left camera at a frame (the right one has right_exposure_gain times it).
  double ExposureGain(int frame) const;

  SyntheticFrame RenderFrame(int frame) const;

 private:
  SynthOptions options_;
  SensorRig rig_;
  std::unique_ptr<Trajectory> trajectory_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<TriangleBvh> bvh_;
  std::unique_ptr<CameraRenderer> renderer_;
  std::unique_ptr<LidarScanner> scanner_;
};

// Pixel counts per label id over label images; shares of the class groups `semap info` reports.
// Not thread-safe to Add() concurrently.
class LabelHistogram {
 public:
  void Add(const cv::Mat& labels);  // CV_8UC1
  void Merge(const LabelHistogram& other);
  std::uint64_t total() const { return total_; }
  std::uint64_t count(Label id) const { return counts_[id]; }
  double Share(Label id) const { return total_ ? static_cast<double>(counts_[id]) / total_ : 0.0; }
  // Share of pixels whose class has this role in `classes` (ground: road/sidewalk/terrain; wall:
  // building/wall/fence for Cityscapes).
  double RoleShare(const ClassMap& classes, ClassRole role) const;

 private:
  std::array<std::uint64_t, 256> counts_{};
  std::uint64_t total_ = 0;
};

}  // namespace semap::sim
