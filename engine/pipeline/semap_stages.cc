#include "engine/pipeline/semap_stages.h"

namespace semap {

StereoLabelStage::StereoLabelStage(const DepthOptions& depth, const SemanticsOptions& semantics, ClassMap class_map)
    : depth_(depth), semantics_(semantics), class_map_(std::move(class_map)), segmenter_(MakeSegmenter(semantics)) {}

LabelledCloud StereoLabelStage::Process(const Frame& frame) {
  LabelledCloud cloud = depth_.Process(frame);
  const cv::Mat labels = FrameLabels(frame, semantics_, segmenter_.get());
  ApplyFirstCameraLabels(cloud, frame.id, labels, frame.left.size(), class_map_.unlabelled_id(),
                         semantics_.size_mismatch);
  return cloud;
}

WindowedSimplifyStage::WindowedSimplifyStage(const SimplifyOptions& options, ClassMap class_map)
    : simplifier_(options, std::move(class_map)) {}

LabelledCloud WindowedSimplifyStage::Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) {
  auto result = simplifier_.Process(cloud);
  for (const auto& c : result.result.per_class) {
    counts->push_back({c.label, static_cast<std::int64_t>(c.in), static_cast<std::int64_t>(c.kept)});
  }
  return std::move(result.kept);
}

}  // namespace semap
