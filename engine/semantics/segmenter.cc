#include "engine/semantics/segmenter.h"

#include <stdexcept>

#include "engine/core/check.h"

namespace semap {
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
  CheckDeclaredRanges(*this);
  if (source == LabelSource::kEnet && enet_model_path.empty()) {
    throw OptionError(*this, enet_model_path,
                      "must name the ENet model file when " + KeyOf(*this, source) + " is " +
                          LabelSourceName(LabelSource::kEnet));
  }
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
