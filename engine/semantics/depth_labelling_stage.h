// The pipeline's depth stage (engine/pipeline/stages.h): stereo depth, then the paper's labelling rule with
// the label image of the configured source (disk, ENet or none).
#pragma once

#include <memory>

#include "engine/depth/stereo_depth.h"
#include "engine/pipeline/stages.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"

namespace semap {

// Not thread-safe (it owns a segmenter): the pipeline creates one instance per depth worker.
class DepthLabellingStage : public DepthStage {
 public:
  // `unlabelled_id`: the id of "no class" in the label images' scheme (the frame source's class map; 0 for
  // ENet's Cityscapes). Throws InvalidOption on bad options and std::runtime_error when ENet cannot load.
  DepthLabellingStage(const DepthOptions& depth, const SemanticsOptions& semantics, Label unlabelled_id);

  // The frame's points in the world frame, labelled from the frame's own label image (points are born in
  // this frame, so it is their first camera). Throws on bad input (see StereoDepth, FrameLabels).
  LabelledCloud Process(const Frame& frame) override;

  // What the last Process() did with the labels (resized = the label image had another size).
  const LabellingReport& last_report() const { return last_report_; }

 private:
  StereoDepth depth_;
  SemanticsOptions semantics_;
  Label unlabelled_id_;
  std::unique_ptr<Segmenter> segmenter_;
  LabellingReport last_report_;
};

}  // namespace semap
