// Image outputs of the depth and semantic stages: KITTI-format disparity PNGs, false-colour disparity and
// label PNGs. Every function throws io::FileError naming the path on a file that cannot be read or written.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>

namespace semap::io {

// KITTI's disparity format: uint16 PNG, value = round(disparity_px · 256), 0 = no disparity. Disparities
// ≤ 0 or non-finite are written as 0; values above 65535 / 256 px are clamped. `disparity_px` is CV_32F.
void WriteKittiDisparityPng(const std::filesystem::path& path, const cv::Mat& disparity_px);
// (Reading: io::ReadKittiDisparityPng in io/kitti/ground_truth.h.)

// A false-colour rendering (BGR, OpenCV's TURBO map, near = red) of a CV_32F disparity, scaled to
// [0, max_disparity_px]; invalid pixels are black. max_disparity_px ≤ 0: the map's maximum.
cv::Mat FalseColourDisparity(const cv::Mat& disparity_px, float max_disparity_px = 0.0f);

// The depth PNG of generated data: uint16, depth in mm (rounded), 0 where `depth_m` (CV_32FC1, metres) is
// 0 or beyond 65.535 m. (Reading: io::ReadDepthPngMm in io/kitti/ground_truth.h.)
void WriteDepthPngMm(const std::filesystem::path& path, const cv::Mat& depth_m);

// Writes any 8-bit image as PNG (label ids CV_8UC1, overlays CV_8UC3 BGR).
void WritePng(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace semap::io
