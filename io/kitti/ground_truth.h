// Ground-truth images beside KITTI-style frames: stereo-2015 disparity PNGs and generated depth PNGs.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>

#include "io/file_error.h"

namespace semap::io {

// KITTI disparity PNG (uint16, disparity = value / 256, 0 = no ground truth) → CV_32FC1 in pixels, 0 where
// there is none. Throws FileError naming the file when it is missing, undecodable or not 16-bit gray.
cv::Mat ReadKittiDisparityPng(const std::filesystem::path& path);

// Depth PNG of a generated sequence (uint16, depth in mm, 0 = none) → CV_32FC1 in metres, 0 = none.
cv::Mat ReadDepthPngMm(const std::filesystem::path& path);

}  // namespace semap::io
