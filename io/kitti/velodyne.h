// KITTI Velodyne scans: .bin files of float32 (x, y, z, reflectance) records, little-endian.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "io/file_error.h"

namespace semap::io {

// Reads a whole scan. Throws FileError naming the file when it is missing, unreadable, its size is not a
// multiple of 16 bytes, or a coordinate is not finite.
std::vector<Eigen::Vector4f> ReadVelodyneBin(const std::filesystem::path& path);

// Writes a scan in the same format (used by tests and the synthetic-sequence generator).
void WriteVelodyneBin(const std::filesystem::path& path, const std::vector<Eigen::Vector4f>& points);

}  // namespace semap::io
