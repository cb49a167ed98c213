#include "engine/semantics/segmenter.h"

#include <stdexcept>

#include "engine/core/check.h"

namespace semap {
namespace {
// Bounds of the network input size: multiples of the encoder's total stride (8) within a sane range.
constexpr int kEnetStride = 8;
constexpr int kEnetMaxInputPx = 4096;
// Keyframe interval bound: beyond this the labels would be carried over far more than the keyframe can see.
constexpr int kMaxEnetEveryFrames = 1000;
}  // namespace

const char* LabelSourceName(LabelSource source) {
  switch (source) {
    case LabelSource::kAuto:
      return "auto";
    case LabelSource::kDisk:
      return "disk";
    case LabelSource::kEnet:
      return "enet";
    case LabelSource::kNone:
      return "none";
  }
  return "?";
}

void SemanticsOptions::Check() const {
  SEMAP_CHECK_OPTION(source != LabelSource::kEnet || !enet_model_path.empty(), "enet_model_path", "(empty)",
                     "must name the ENet model file when source is enet");
  SEMAP_CHECK_OPTION(enet_input_width_px >= kEnetStride && enet_input_width_px <= kEnetMaxInputPx &&
                         enet_input_width_px % kEnetStride == 0,
                     "enet_input_width_px", enet_input_width_px, "must be a multiple of 8 in [8, 4096]");
  SEMAP_CHECK_OPTION(enet_input_height_px >= kEnetStride && enet_input_height_px <= kEnetMaxInputPx &&
                         enet_input_height_px % kEnetStride == 0,
                     "enet_input_height_px", enet_input_height_px, "must be a multiple of 8 in [8, 4096]");
  SEMAP_CHECK_OPTION(enet_every_frames >= 1 && enet_every_frames <= kMaxEnetEveryFrames, "enet_every_frames",
                     enet_every_frames, "must be in [1, 1000] (1 = ENet on every frame)");
  SEMAP_CHECK_OPTION(enet_threads >= 0, "enet_threads", enet_threads, "must be >= 0 (0 = OpenCV's setting)");
}

std::unique_ptr<Segmenter> MakeSegmenter(const SemanticsOptions& options) {
  options.Check();
  if (options.source == LabelSource::kEnet) return std::make_unique<EnetSegmenter>(options);
  return nullptr;
}

cv::Mat FrameLabels(const Frame& frame, const SemanticsOptions& options, Segmenter* segmenter) {
  switch (options.source) {
    case LabelSource::kAuto:
      return frame.labels;
    case LabelSource::kDisk:
      if (frame.labels.empty()) {
        throw std::runtime_error("frame " + std::to_string(frame.id) +
                                 " has no label image (semantics.source is disk: set input.labels_dir, or "
                                 "use source auto, enet or none)");
      }
      return frame.labels;
    case LabelSource::kEnet:
      SEMAP_ASSERT(segmenter != nullptr, "semantics.source enet needs a segmenter");
      return segmenter->Segment(frame.left);
    case LabelSource::kNone:
      return cv::Mat();
  }
  return cv::Mat();
}

}  // namespace semap
