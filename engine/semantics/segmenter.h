// Where per-pixel labels come from: label images read from disk, a built-in segmenter, or none.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "engine/core/class_map.h"
#include "engine/core/frame.h"
#include "engine/semantics/keyframe_labels.h"
#include "engine/semantics/labelling.h"

namespace semap {

enum class LabelSource {
  kAuto,  // the frame's label image (frame.labels, read from disk) when it has one, else unlabelled
  kDisk,  // the frame's label image; a frame without one is an error
  kEnet,  // the built-in ENet Cityscapes segmenter
  kNone,  // every point unlabelled: nothing is simplified semantically
};

const char* LabelSourceName(LabelSource source);

struct SemanticsOptions {
  LabelSource source = LabelSource::kAuto;
  // ENet Cityscapes model (Torch7 .net file, read with cv::dnn::readNetFromTorch).
  std::string enet_model_path = "../shared/models/enet-cityscapes/enet-model.net";
  // Network input size in px (the model was trained at 1024x512).
  int enet_input_width_px = 1024;
  int enet_input_height_px = 512;
  // Keep the image's aspect ratio: scale it to fit the network input and pad the rest (border replicated)
  // instead of stretching it. KITTI's 1242×375 frames stretched to 1024×512 look nothing like Cityscapes.
  bool enet_keep_aspect = true;
  // Threads of the network's forward pass (cv::setNumThreads is process-wide: 0 = leave OpenCV's setting).
  int enet_threads = 0;
  // ENet in `semap run` (the streaming pipeline) runs on its own thread, on keyframes only: the first frame,
  // then every enet_every_frames frames. Frames between keyframes take the labels of the nearest earlier
  // keyframe as enet_propagation says (see keyframe_labels.h). 1 = every frame, segmented in the depth workers
  // (each its own network, frames in parallel), as before keyframes. The default keeps a run with ENet labels
  // near the frame rate of a run with label files at no measured loss of label accuracy (bench/RESULTS.md,
  // "ENet off the critical path"). Outside the pipeline (compare --mode single-frame, depth, segment) every
  // frame is segmented.
  int enet_every_frames = 6;
  // How a frame between keyframes gets its labels: reproject (through its depth and the relative pose) or
  // reuse (the keyframe's label image as it is).
  LabelPropagation enet_propagation = LabelPropagation::kReproject;
  // A label image of another size than the left image: resize with nearest neighbour (and report it) or
  // refuse (error).
  LabelSizePolicy size_mismatch = LabelSizePolicy::kResizeNearest;
  // Points whose pixel is labelled sky (the class map's class named "sky", e.g. Cityscapes 11, the label of
  // the generated sequences' pixels without surface) give no point: texture-less sky matched by SGBM is no
  // surface, and its points close the map with a ceiling over the street. Nothing happens with a class map
  // without a sky class or with unlabelled frames.
  bool drop_sky = true;

  void Check() const;
};

// A semantic segmenter: image → label image. Implementations are not thread-safe (one network per
// instance): use one instance per thread.
class Segmenter {
 public:
  virtual ~Segmenter() = default;
  // Label image (CV_8UC1, ids of class_map()) of the same size as `image` (CV_8UC3 BGR or CV_8UC1 grey).
  // Throws std::invalid_argument on an empty image or an unsupported type.
  virtual cv::Mat Segment(const cv::Mat& image) = 0;
  virtual const ClassMap& class_map() const = 0;
  virtual std::string name() const = 0;
};

// ENet (Paszke et al. 2016) trained on Cityscapes, through OpenCV's dnn module: input RGB (swapRB) scaled by
// 1/255 to enet_input_{width,height}_px, output 1×20×H×W scores → argmax → nearest-neighbour resize back
// to the image. Labels are ClassMap::Cityscapes() ids.
class EnetSegmenter : public Segmenter {
 public:
  // Throws std::runtime_error naming the path when the model file is missing or does not load as a network.
  explicit EnetSegmenter(const SemanticsOptions& options);
  ~EnetSegmenter() override;
  EnetSegmenter(const EnetSegmenter&) = delete;
  EnetSegmenter& operator=(const EnetSegmenter&) = delete;

  cv::Mat Segment(const cv::Mat& image) override;
  const ClassMap& class_map() const override { return class_map_; }
  std::string name() const override { return "enet-cityscapes"; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  SemanticsOptions options_;
  ClassMap class_map_;
};

// The segmenter of options.source (kEnet), or nullptr for the sources that need none.
std::unique_ptr<Segmenter> MakeSegmenter(const SemanticsOptions& options);

// The label image of `frame` according to options.source: frame.labels (kAuto, kDisk), segmenter->Segment
// (kEnet; requires a segmenter), or an empty Mat (kNone, or kAuto without labels: all points unlabelled).
// Throws std::runtime_error for kDisk when the frame has no label image.
cv::Mat FrameLabels(const Frame& frame, const SemanticsOptions& options, Segmenter* segmenter);

}  // namespace semap
