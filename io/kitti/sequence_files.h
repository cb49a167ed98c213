// Per-sequence KITTI text files: raw timestamps.txt, odometry times.txt and poses/NN.txt.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io {

// Seconds since midnight (UTC day count included) of "2011-09-26 13:02:25.964389445"; throws
// FileError(path) naming the line on a malformed stamp.
double ParseKittiTimestamp(const std::string& text, const std::filesystem::path& path, int line_no);

// A raw `timestamps.txt`: one stamp per line → seconds since the first line. Throws FileError(path).
std::vector<double> ReadKittiTimestamps(const std::filesystem::path& path);

// An odometry `times.txt`: one time in seconds per line → seconds since the first line.
std::vector<double> ReadOdometryTimes(const std::filesystem::path& path);

// An odometry poses file: each line 12 numbers, the 3×4 row-major world_from_cam0. Reads the first
// `count` lines; throws FileError(path) when the file has fewer lines than `count` (naming both numbers)
// or a line is malformed (naming the line).
std::vector<Pose3d> ReadOdometryPoses(const std::filesystem::path& path, size_t count);

}  // namespace semap::io
