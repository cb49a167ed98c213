#include "io/image/image_files.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/file_error.h"

namespace semap::io {
namespace {
// KITTI stores disparity · 256 in 16 bits.
constexpr double kKittiDisparityScale = 256.0;
constexpr double kMaxUint16 = 65535.0;

void Write(const std::filesystem::path& path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), image);
  } catch (const cv::Exception& e) {
    throw FileError(path, std::string("cannot write the image: ") + e.what());
  }
  if (!ok) throw FileError(path, "cannot write the image (missing folder or no permission?)");
}
}  // namespace

void WriteKittiDisparityPng(const std::filesystem::path& path, const cv::Mat& disparity_px) {
  if (disparity_px.empty() || disparity_px.type() != CV_32FC1) {
    throw FileError(path, "the disparity to write must be a non-empty CV_32F image");
  }
  cv::Mat out(disparity_px.size(), CV_16UC1);
  for (int v = 0; v < disparity_px.rows; ++v) {
    const float* d = disparity_px.ptr<float>(v);
    std::uint16_t* o = out.ptr<std::uint16_t>(v);
    for (int u = 0; u < disparity_px.cols; ++u) {
      const double scaled =
          std::isfinite(d[u]) && d[u] > 0.0f ? std::round(d[u] * kKittiDisparityScale) : 0.0;
      o[u] = static_cast<std::uint16_t>(std::min(scaled, kMaxUint16));
    }
  }
  Write(path, out);
}

void WriteDepthPngMm(const std::filesystem::path& path, const cv::Mat& depth_m) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1) {
    throw FileError(path, "the depth to write must be a non-empty CV_32F image");
  }
  cv::Mat out(depth_m.size(), CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* d = depth_m.ptr<float>(v);
    std::uint16_t* o = out.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      const double mm = std::round(static_cast<double>(d[u]) * 1000.0);
      o[u] = (mm > 0.0 && mm <= kMaxUint16) ? static_cast<std::uint16_t>(mm) : 0;
    }
  }
  Write(path, out);
}

cv::Mat FalseColourDisparity(const cv::Mat& disparity_px, float max_disparity_px) {
  CV_Assert(disparity_px.type() == CV_32FC1);
  cv::Mat valid = disparity_px > 0.0f;
  cv::Mat clean;
  disparity_px.copyTo(clean);
  clean.setTo(0.0f, ~valid);  // negative, zero and NaN → 0
  double max_value = max_disparity_px;
  if (max_value <= 0.0) cv::minMaxLoc(clean, nullptr, &max_value);
  cv::Mat scaled, colour;
  clean.convertTo(scaled, CV_8U, max_value > 0.0 ? 255.0 / max_value : 0.0);
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar(0, 0, 0), ~valid);
  return colour;
}

void WritePng(const std::filesystem::path& path, const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U) throw FileError(path, "the image to write must be 8-bit");
  Write(path, image);
}

}  // namespace semap::io
