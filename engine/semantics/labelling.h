// The paper's labelling rule (Sec. III): "we project each point of the dense point cloud into the segmented
// image corresponding to the first camera which observed it and we label p_i according to the class of the
// pixel where the point is projected".
//
// In semap's streaming pipeline a point is born in the frame whose disparity produced it, so its first
// observing camera is that frame's left camera (LabelledCloud::camera_index) and its pixel there is
// LabelledCloud::pixels_px. The contract, made explicit here:
//   1. ApplyFirstCameraLabels(cloud, frame_id, label_image) labels exactly the points whose FIRST camera is
//      `frame_id`, from their pixel in that frame's label image;
//   2. points first observed by another camera are never relabelled, even if they also project into this
//      image (a re-observation): KeepFirstLabel() is the rule every merge of observations must use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"

namespace semap {

// What to do with a label image whose size differs from the image the points were measured in.
enum class LabelSizePolicy {
  kResizeNearest,  // rescale it with nearest neighbour (labels never blend) and report it (resized = true)
  kRefuse,         // throw std::invalid_argument naming both sizes
};

// The label of a point after an observation: the first camera's label wins. `first` is the label from the
// first camera that observed the point (nullopt when no camera has labelled it yet).
inline Label KeepFirstLabel(std::optional<Label> first, Label observed) { return first.value_or(observed); }

struct LabellingReport {
  std::size_t labelled = 0;       // points of this camera that received a label
  std::size_t outside_image = 0;  // points of this camera whose pixel fell outside (→ unlabelled id)
  std::size_t other_cameras = 0;  // points first observed by another camera (left unchanged)
  bool resized = false;           // the label image was rescaled to the image size (kResizeNearest)
};

// Labels the points of `cloud` whose first camera (camera_frame_ids[camera_index[i]]) is `frame_id` with
// label_image(v, u) at their pixel (u, v) = pixels_px[i] (rounded to the nearest pixel). `label_image` is
// CV_8UC1 in the ClassMap id scheme; `image_size` is the size of the image the pixels refer to (the left
// image). If cloud.labels is absent it is created, filled with `unlabelled_id`. An empty label image labels
// this camera's points `unlabelled_id` (label source "none"). Requires pixels_px and camera indices
// (programmer error otherwise); throws std::invalid_argument on a label image that is not CV_8UC1 or, under
// kRefuse, of another size.
LabellingReport ApplyFirstCameraLabels(LabelledCloud& cloud, std::int64_t frame_id,
                                       const cv::Mat& label_image, cv::Size image_size, Label unlabelled_id,
                                       LabelSizePolicy policy = LabelSizePolicy::kResizeNearest);

// The sky class of `class_map`: the class named "sky" (case-insensitive), or nullopt when it has none.
std::optional<Label> SkyLabel(const ClassMap& class_map);

// Removes the points of `cloud` labelled `label` (requires labels, programmer error otherwise); returns how
// many were removed. The other points keep their order and every attribute.
std::size_t RemoveLabel(LabelledCloud& cloud, Label label);

// `label_image` as a colour image (BGR) using the class map's display colours; unknown ids are black.
cv::Mat ColorizeLabels(const cv::Mat& label_image, const ClassMap& class_map);

// The colourised labels blended over `image` (grey or BGR of the same size): alpha = weight of the labels.
cv::Mat OverlayLabels(const cv::Mat& image, const cv::Mat& label_image, const ClassMap& class_map,
                      double alpha);

}  // namespace semap
