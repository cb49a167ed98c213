#include "engine/semantics/depth_labelling_stage.h"

namespace semap {

DepthLabellingStage::DepthLabellingStage(const DepthOptions& depth, const SemanticsOptions& semantics,
                                         Label unlabelled_id)
    : depth_(depth), semantics_(semantics), unlabelled_id_(unlabelled_id), segmenter_(MakeSegmenter(semantics)) {}

LabelledCloud DepthLabellingStage::Process(const Frame& frame) {
  LabelledCloud cloud = depth_.Process(frame);
  const cv::Mat labels = FrameLabels(frame, semantics_, segmenter_.get());
  last_report_ = ApplyFirstCameraLabels(cloud, frame.id, labels, frame.left.size(), unlabelled_id_,
                                        semantics_.size_mismatch);
  return cloud;
}

}  // namespace semap
