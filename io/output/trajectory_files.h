// Camera trajectories as text: the KITTI odometry pose format and the TUM RGB-D format.
#pragma once

#include <filesystem>
#include <vector>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io {

// KITTI pose format: one line per frame, the 3×4 world_from_cam row-major (12 numbers). Written atomically;
// throws FileError.
void WriteKittiPoses(const std::filesystem::path& path, const std::vector<Pose3d>& world_from_cam);

// Every pose of a KITTI pose file (io/kitti ReadOdometryPoses checks each line). Throws FileError.
std::vector<Pose3d> ReadKittiPoses(const std::filesystem::path& path);

struct StampedPose {
  double timestamp_s = 0.0;
  Pose3d world_from_cam = Pose3d::Identity();
};

// TUM format: "timestamp tx ty tz qx qy qz qw" per line (seconds, metres, unit quaternion). Written
// atomically; throws FileError.
void WriteTumTrajectory(const std::filesystem::path& path, const std::vector<StampedPose>& poses);

// A TUM trajectory; lines starting with '#' and blank lines are skipped. Throws FileError naming the line
// when one is not 8 finite numbers or its quaternion is far from unit length.
std::vector<StampedPose> ReadTumTrajectory(const std::filesystem::path& path);

}  // namespace semap::io
