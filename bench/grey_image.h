// The grey image the bench programs match on: a grey frame as it is, a BGR frame converted.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace semap::bench {

inline cv::Mat Gray(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

}  // namespace semap::bench
