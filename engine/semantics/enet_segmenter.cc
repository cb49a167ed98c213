#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/semantics/segmenter.h"

namespace semap {
namespace {
// ENet's input normalisation: pixel values scaled to [0, 1].
constexpr double kEnetInputScale = 1.0 / 255.0;
// The fused head is checked against OpenCV's last layer on a random input of this size (a multiple of ENet's
// stride of 8), seeded for the same check every time.
constexpr int kHeadCheckWidthPx = 64;
constexpr int kHeadCheckHeightPx = 32;
constexpr std::uint64_t kHeadCheckSeed = 7;
// Largest difference of a class score, relative to the largest score, that float rounding explains.
constexpr float kHeadCheckRelativeTolerance = 1e-4f;
// The head's geometry: a transposed convolution with a 2×2 kernel and stride 2 (each input cell gives a 2×2
// block of output cells, one weight matrix per position in the block).
constexpr int kHeadUpsampling = 2;
// Input rows the head scores at once (its scores, classes × rows × width floats, stay in the caches).
constexpr int kHeadBlockRows = 4;

using RowMajorMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The index of the largest of `n` scores, the first on ties (as the network path's argmax).
std::uint8_t ArgMax(const float* scores, int n) {
  int best = 0;
  for (int k = 1; k < n; ++k) {
    if (scores[k] > scores[best]) best = k;
  }
  return static_cast<std::uint8_t>(best);
}

// ENet's last layer, out[k, 2y + a, 2x + b] = bias[k] + sum_c in[c, y, x] W[c, k, a, b], evaluated here.
struct FusedHead {
  std::string input_layer;  // the layer whose output (1 × channels × H × W) the head reads
  int channels = 0;
  int classes = 0;
  std::array<Eigen::MatrixXf, kHeadUpsampling * kHeadUpsampling> weights;  // [a * 2 + b]: classes × channels
  Eigen::VectorXf bias;

  // Calls visit(out_row, out_col, scores) for every output cell of the output rows [row0, row1) (scores:
  // `classes` floats, valid during the call).
  template <typename Visit>
  void Score(const cv::Mat& features, int row0, int row1, Visit&& visit) const {
    const int h = features.size[2];
    const int w = features.size[3];
    const Eigen::Map<const RowMajorMatrixXf> in(features.ptr<float>(), channels,
                                                static_cast<Eigen::Index>(h) * w);
    Eigen::MatrixXf scores;
    for (int y0 = row0 / kHeadUpsampling; y0 * kHeadUpsampling < row1 && y0 < h; y0 += kHeadBlockRows) {
      const int rows = std::min(kHeadBlockRows, h - y0);
      const auto block =
          in.middleCols(static_cast<Eigen::Index>(y0) * w, static_cast<Eigen::Index>(rows) * w);
      for (int a = 0; a < kHeadUpsampling; ++a) {
        for (int b = 0; b < kHeadUpsampling; ++b) {
          scores.noalias() = weights[a * kHeadUpsampling + b] * block;
          scores.colwise() += bias;
          for (Eigen::Index j = 0; j < scores.cols(); ++j) {
            const int out_row = (y0 + static_cast<int>(j / w)) * kHeadUpsampling + a;
            if (out_row < row0 || out_row >= row1) continue;
            visit(out_row, static_cast<int>(j % w) * kHeadUpsampling + b, scores.col(j).data());
          }
        }
      }
    }
  }
};

// The fused head of `net`'s last layer, or nothing when that layer is not a 2×2 stride-2 transposed
// convolution whose input is the layer before it, or when it does not reproduce OpenCV's scores. `net` is a
// network of its own for this check: OpenCV 4.6 can give wrong outputs when one network is run at another
// input size with another set of requested outputs than before.
std::optional<FusedHead> MakeFusedHead(cv::dnn::Net net) {
  const std::vector<cv::String> names = net.getLayerNames();
  const std::vector<int> outputs = net.getUnconnectedOutLayers();
  if (names.size() < 2 || outputs.size() != 1 || net.getLayerId(names.back()) != outputs[0])
    return std::nullopt;
  const cv::Ptr<cv::dnn::Layer> last = net.getLayer(outputs[0]);
  const auto deconv = last.dynamicCast<cv::dnn::BaseConvolutionLayer>();
  const std::vector<size_t> two{kHeadUpsampling, kHeadUpsampling};
  const std::vector<size_t> zero{0, 0};
  if (last->type != "Deconvolution" || !deconv || deconv->kernel_size != two || deconv->strides != two ||
      deconv->pads_begin != zero || deconv->pads_end != zero ||
      (!deconv->adjust_pads.empty() && deconv->adjust_pads != zero) ||
      deconv->dilations != std::vector<size_t>{1, 1} || last->blobs.empty() || last->blobs[0].dims != 4 ||
      last->blobs[0].type() != CV_32F || last->blobs[0].size[2] != kHeadUpsampling ||
      last->blobs[0].size[3] != kHeadUpsampling) {
    return std::nullopt;
  }
  FusedHead head;
  head.input_layer = names[names.size() - 2];
  const cv::Mat& w = last->blobs[0];  // channels × classes × 2 × 2
  head.channels = w.size[0];
  head.classes = w.size[1];
  if (head.classes < 1 || head.classes > 256 || head.channels < 1) return std::nullopt;
  head.bias = Eigen::VectorXf::Zero(head.classes);
  if (last->blobs.size() > 1) {
    const cv::Mat& bias = last->blobs[1];
    if (bias.total() != static_cast<size_t>(head.classes) || bias.type() != CV_32F) return std::nullopt;
    for (int k = 0; k < head.classes; ++k) head.bias[k] = bias.ptr<float>()[k];
  }
  const float* wp = w.ptr<float>();
  for (int a = 0; a < kHeadUpsampling; ++a) {
    for (int b = 0; b < kHeadUpsampling; ++b) {
      Eigen::MatrixXf& m = head.weights[a * kHeadUpsampling + b];
      m.resize(head.classes, head.channels);
      for (int c = 0; c < head.channels; ++c) {
        for (int k = 0; k < head.classes; ++k) {
          m(k, c) =
              wp[((static_cast<size_t>(c) * head.classes + k) * kHeadUpsampling + a) * kHeadUpsampling + b];
        }
      }
    }
  }
  // The check: both outputs of one pass on a random input, the head's scores against OpenCV's.
  cv::Mat probe(kHeadCheckHeightPx, kHeadCheckWidthPx, CV_8UC3);
  cv::RNG rng(kHeadCheckSeed);
  rng.fill(probe, cv::RNG::UNIFORM, 0, 256);
  net.setInput(cv::dnn::blobFromImage(probe, kEnetInputScale, probe.size(), cv::Scalar(), true, false));
  std::vector<cv::Mat> outs;
  net.forward(outs, std::vector<cv::String>{head.input_layer, names.back()});
  const cv::Mat& features = outs[0];
  const cv::Mat& scores = outs[1];
  if (features.dims != 4 || scores.dims != 4 || features.size[0] != 1 || features.size[1] != head.channels ||
      scores.size[1] != head.classes || scores.size[2] != kHeadUpsampling * features.size[2] ||
      scores.size[3] != kHeadUpsampling * features.size[3]) {
    return std::nullopt;
  }
  double max_score = 0.0;
  cv::minMaxIdx(cv::abs(scores), nullptr, &max_score);
  const size_t plane = static_cast<size_t>(scores.size[2]) * scores.size[3];
  const float* s = scores.ptr<float>();
  bool same = true;
  head.Score(features, 0, scores.size[2], [&](int row, int col, const float* fused) {
    for (int k = 0; k < head.classes && same; ++k) {
      const float reference = s[k * plane + static_cast<size_t>(row) * scores.size[3] + col];
      same = std::abs(fused[k] - reference) <= kHeadCheckRelativeTolerance * static_cast<float>(max_score);
    }
  });
  if (!same) return std::nullopt;
  return head;
}
// The output cells (h × w) that hold the image's region `roi` of the network input `input`.
cv::Rect OutputRoi(const cv::Rect& roi, const cv::Size& input, int h, int w) {
  const double sx = double(w) / input.width;
  const double sy = double(h) / input.height;
  return cv::Rect(static_cast<int>(roi.x * sx), static_cast<int>(roi.y * sy),
                  std::max(1, static_cast<int>(roi.width * sx)),
                  std::max(1, static_cast<int>(roi.height * sy))) &
         cv::Rect(0, 0, w, h);
}
}  // namespace

struct EnetSegmenter::Impl {
  cv::dnn::Net net;
  std::optional<FusedHead> head;  // set when the fused head is in use
};

EnetSegmenter::EnetSegmenter(const SemanticsOptions& options, EnetHead head)
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
  if (head == EnetHead::kFused) impl_->head = MakeFusedHead(cv::dnn::readNetFromTorch(path.string()));
}

EnetSegmenter::~EnetSegmenter() = default;

EnetHead EnetSegmenter::head() const { return impl_->head ? EnetHead::kFused : EnetHead::kNetwork; }

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
  if (impl_->head) {
    const FusedHead& head = *impl_->head;
    const cv::Mat features = impl_->net.forward(head.input_layer);  // 1 × channels × H/2 × W/2
    if (features.dims != 4 || features.size[0] != 1 || features.size[1] != head.channels ||
        features.type() != CV_32F || !features.isContinuous()) {
      throw std::runtime_error("ENet: unexpected features before the last layer (dims " +
                               std::to_string(features.dims) + ")");
    }
    const int h = kHeadUpsampling * features.size[2];
    const int w = kHeadUpsampling * features.size[3];
    const cv::Rect out_roi = OutputRoi(roi, input, h, w);
    cv::Mat labels(out_roi.height, w, CV_8UC1);
    head.Score(features, out_roi.y, out_roi.y + out_roi.height, [&](int row, int col, const float* scores) {
      labels.at<std::uint8_t>(row - out_roi.y, col) = ArgMax(scores, head.classes);
    });
    cv::Mat out;
    cv::resize(labels.colRange(out_roi.x, out_roi.x + out_roi.width), out, image.size(), 0.0, 0.0,
               cv::INTER_NEAREST);
    return out;
  }
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
  const cv::Rect out_roi = OutputRoi(roi, input, h, w);
  cv::Mat out;
  cv::resize(labels(out_roi), out, image.size(), 0.0, 0.0, cv::INTER_NEAREST);
  return out;
}

}  // namespace semap
