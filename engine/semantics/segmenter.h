// Where per-pixel labels come from: label images read from disk, a built-in segmenter, or none.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "engine/core/class_map.h"
#include "engine/core/frame.h"
#include "engine/core/options.h"
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
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  LabelSource source = LabelSource::kAuto;
  std::string enet_model_path = "../shared/models/enet-cityscapes/enet-model.net";
  int enet_input_width_px = 1024;  // the model was trained at 1024x512
  int enet_input_height_px = 512;
  bool enet_keep_aspect = true;
  int enet_every_frames = 6;
  LabelPropagation enet_propagation = LabelPropagation::kReproject;
  LabelSizePolicy size_mismatch = LabelSizePolicy::kResizeNearest;
  bool drop_sky = true;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    // The network input size: a multiple of the encoder's total stride within a sane range.
    constexpr int kEnetStride = 8;
    constexpr int kEnetMaxInputPx = 4096;
    const Range input_px = In(kEnetStride, kEnetMaxInputPx).MultipleOf(kEnetStride);
    v.Enum("source", &source,
           {{"auto", LabelSource::kAuto},
            {"disk", LabelSource::kDisk},
            {"enet", LabelSource::kEnet},
            {"none", LabelSource::kNone}},
           "label source: auto = label images from disk when present else unlabelled, enet = built-in "
           "segmenter");
    v.Field(
        "enet_model_path", &enet_model_path,
        "ENet Cityscapes Torch7 model file (read with cv::dnn::readNetFromTorch); needed with source enet");
    v.Field("enet_input_width_px", &enet_input_width_px, "ENet input width in px", input_px);
    v.Field("enet_input_height_px", &enet_input_height_px, "ENet input height in px", input_px);
    // KITTI's 1242×375 frames stretched to 1024×512 look nothing like Cityscapes.
    v.Field(
        "enet_keep_aspect", &enet_keep_aspect,
        "keep the image's aspect ratio in the network input (scale to fit, pad with the border replicated) "
        "instead of stretching it");
    // Beyond this the labels would be carried over far more than the keyframe can see.
    constexpr int kMaxEnetEveryFrames = 1000;
    // The default keeps a run with ENet labels near the frame rate of a run with label files at no measured
    // loss of label accuracy (bench/results/semantic-labels.md, "ENet off the critical path"). Outside the
    // pipeline (compare --mode single-frame, depth, segment) every frame is segmented. See keyframe_labels.h.
    v.Field(
        "enet_every_frames", &enet_every_frames,
        "semap run: ENet on its own thread on keyframes only, the first frame then every enet_every_frames "
        "frames (1 = every frame, in the depth workers, each its own network)",
        In(1, kMaxEnetEveryFrames));
    v.Enum(
        "enet_propagation", &enet_propagation,
        {{"reproject", LabelPropagation::kReproject}, {"reuse", LabelPropagation::kReuse}},
        "labels of frames between keyframes: reproject the keyframe's (frame depth + relative pose) or reuse "
        "them as they are");
    v.Enum("size_mismatch", &size_mismatch,
           {{"resize", LabelSizePolicy::kResizeNearest}, {"refuse", LabelSizePolicy::kRefuse}},
           "label image of another size than the image: resize with nearest neighbour (warned) or refuse");
    // Texture-less sky matched by SGBM is no surface, and its points close the map with a ceiling over the
    // street. The generated sequences label their pixels without surface sky.
    v.Field(
        "drop_sky", &drop_sky,
        "pixels labelled sky (the class map's class named sky, e.g. Cityscapes 11) give no point; nothing "
        "happens with a class map without sky or with unlabelled frames");
  }

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
//
// The network's last layer (a 2×2, stride-2 transposed convolution from 16 feature channels to the 20 class
// scores at full resolution) is evaluated by the segmenter itself, only on the output rows that hold the
// image, and fused with the argmax (EnetHead::kFused): OpenCV computes it over the whole padded output and
// it was the network's costliest layer. The constructor checks the fused head against OpenCV's own layer
// on a small input and keeps OpenCV's (kNetwork) when the model's last layer is anything else or disagrees.
enum class EnetHead {
  kFused,    // the last layer computed here, on the image's rows, fused with the argmax (when it checks out)
  kNetwork,  // the whole network in OpenCV, argmax over its full output (the reference)
};

class EnetSegmenter : public Segmenter {
 public:
  // Throws std::runtime_error naming the path when the model file is missing or does not load as a network.
  explicit EnetSegmenter(const SemanticsOptions& options, EnetHead head = EnetHead::kFused);
  ~EnetSegmenter() override;
  EnetSegmenter(const EnetSegmenter&) = delete;
  EnetSegmenter& operator=(const EnetSegmenter&) = delete;

  cv::Mat Segment(const cv::Mat& image) override;
  const ClassMap& class_map() const override { return class_map_; }
  std::string name() const override { return "enet-cityscapes"; }
  // The head in use: kFused only when it was asked for and the model's last layer checked out.
  EnetHead head() const;

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
