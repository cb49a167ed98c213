#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "engine/core/check.h"
#include "engine/semantics/segmenter.h"

namespace semap {
namespace {
// ENet's input normalisation: pixel values scaled to [0, 1].
constexpr double kEnetInputScale = 1.0 / 255.0;
}  // namespace

struct EnetSegmenter::Impl {
  cv::dnn::Net net;
};

EnetSegmenter::EnetSegmenter(const SemanticsOptions& options)
    : impl_(std::make_unique<Impl>()), options_(options), class_map_(ClassMap::Cityscapes()) {
  options_.Check();
  const std::filesystem::path path(options_.enet_model_path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw std::runtime_error("ENet model " + path.string() +
                             ": file not found (set semantics.enet_model_path)");
  }
  try {
    impl_->net = cv::dnn::readNetFromTorch(path.string());
  } catch (const cv::Exception& e) {
    throw std::runtime_error("ENet model " + path.string() + ": not a Torch7 network OpenCV can load (" +
                             e.msg + ")");
  }
  if (impl_->net.empty()) {
    throw std::runtime_error("ENet model " + path.string() + ": the file holds no network");
  }
  impl_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  impl_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
}

EnetSegmenter::~EnetSegmenter() = default;

cv::Mat EnetSegmenter::Segment(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("ENet: the image is empty");
  if (image.type() != CV_8UC3 && image.type() != CV_8UC1) {
    throw std::invalid_argument("ENet: the image must be 8-bit BGR or grey, got type " +
                                std::to_string(image.type()));
  }
  cv::Mat bgr;
  if (image.channels() == 1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else {
    bgr = image;
  }
  if (options_.enet_threads > 0) cv::setNumThreads(options_.enet_threads);
  const cv::Size input(options_.enet_input_width_px, options_.enet_input_height_px);
  // Region of the network input that holds the image (all of it unless the aspect ratio is kept).
  cv::Rect roi(0, 0, input.width, input.height);
  cv::Mat network_image;
  if (options_.enet_keep_aspect) {
    const double scale = std::min(double(input.width) / bgr.cols, double(input.height) / bgr.rows);
    roi.width = std::clamp(static_cast<int>(std::lround(bgr.cols * scale)), 1, input.width);
    roi.height = std::clamp(static_cast<int>(std::lround(bgr.rows * scale)), 1, input.height);
    roi.x = (input.width - roi.width) / 2;
    roi.y = (input.height - roi.height) / 2;
    cv::Mat scaled;
    cv::resize(bgr, scaled, roi.size(), 0.0, 0.0, cv::INTER_AREA);
    cv::copyMakeBorder(scaled, network_image, roi.y, input.height - roi.height - roi.y, roi.x,
                       input.width - roi.width - roi.x, cv::BORDER_REPLICATE);
  } else {
    cv::resize(bgr, network_image, input, 0.0, 0.0, cv::INTER_AREA);
  }
  const cv::Mat blob = cv::dnn::blobFromImage(network_image, kEnetInputScale, input, cv::Scalar(),
                                              /*swapRB=*/true, /*crop=*/false);
  impl_->net.setInput(blob);
  const cv::Mat scores = impl_->net.forward();  // 1 × C × H × W
  if (scores.dims != 4 || scores.size[0] != 1) {
    throw std::runtime_error("ENet: unexpected output shape (dims " + std::to_string(scores.dims) + ")");
  }
  const int num_classes = scores.size[1];
  const int h = scores.size[2];
  const int w = scores.size[3];
  if (num_classes < 1 || num_classes > 256) {
    throw std::runtime_error("ENet: unexpected number of classes " + std::to_string(num_classes));
  }
  const float* data = scores.ptr<float>();
  const size_t plane = static_cast<size_t>(h) * static_cast<size_t>(w);
  cv::Mat best_score = cv::Mat(h, w, CV_32F, const_cast<float*>(data)).clone();
  cv::Mat labels = cv::Mat::zeros(h, w, CV_8UC1);
  for (int c = 1; c < num_classes; ++c) {
    const cv::Mat channel(h, w, CV_32F, const_cast<float*>(data + c * plane));
    for (int v = 0; v < h; ++v) {
      const float* s = channel.ptr<float>(v);
      float* best = best_score.ptr<float>(v);
      std::uint8_t* l = labels.ptr<std::uint8_t>(v);
      for (int u = 0; u < w; ++u) {
        if (s[u] > best[u]) {
          best[u] = s[u];
          l[u] = static_cast<std::uint8_t>(c);
        }
      }
    }
  }
  // Output cells → input pixels (the output may be smaller than the input), then back to the image.
  const double sx = double(w) / input.width;
  const double sy = double(h) / input.height;
  const cv::Rect out_roi = cv::Rect(static_cast<int>(roi.x * sx), static_cast<int>(roi.y * sy),
                                    std::max(1, static_cast<int>(roi.width * sx)),
                                    std::max(1, static_cast<int>(roi.height * sy))) &
                           cv::Rect(0, 0, w, h);
  cv::Mat out;
  cv::resize(labels(out_roi), out, image.size(), 0.0, 0.0, cv::INTER_NEAREST);
  return out;
}

}  // namespace semap
