#include "io/kitti/ground_truth.h"

#include <opencv2/imgcodecs.hpp>

namespace semap::io {
namespace {

// KITTI stores disparities as value / 256.
constexpr double kDisparityScale = 1.0 / 256.0;
constexpr double kMillimetresToMetres = 1e-3;

cv::Mat ReadUint16(const std::filesystem::path& path, const char* what) {
  if (!std::filesystem::is_regular_file(path)) throw FileError(path, std::string(what) + " not found");
  cv::Mat m;
  try {
    m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw FileError(path, std::string("cannot decode ") + what + ": " + e.what());
  }
  if (m.empty()) throw FileError(path, std::string("cannot decode ") + what + " (truncated or corrupt PNG)");
  if (m.type() != CV_16UC1) throw FileError(path, std::string(what) + " must be a 16-bit single-channel PNG");
  return m;
}

}  // namespace

cv::Mat ReadKittiDisparityPng(const std::filesystem::path& path) {
  cv::Mat out;
  ReadUint16(path, "disparity image").convertTo(out, CV_32F, kDisparityScale);
  return out;
}

cv::Mat ReadDepthPngMm(const std::filesystem::path& path) {
  cv::Mat out;
  ReadUint16(path, "depth image").convertTo(out, CV_32F, kMillimetresToMetres);
  return out;
}

}  // namespace semap::io
