// Labels of keyframes carried to the frames between them, so that a slow segmenter (ENet: ~0.45 s per frame
// on one core) runs on keyframes only (semantics.enet_every_frames) and off the pipeline's critical path.
//
// A frame between keyframes takes the labels of the nearest earlier keyframe, either reprojected (each pixel
// of the frame is lifted with its own depth, moved by the relative pose into the keyframe's camera and given
// the keyframe's label where it lands) or reused as they are (the keyframe's label at the same pixel).
// Everything here is a pure function of its inputs: no dependence on threads or timing.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>

#include "engine/core/calibration.h"
#include "engine/core/class_map.h"

namespace semap {

// How a frame between keyframes gets its labels.
enum class LabelPropagation {
  kReproject,  // through the frame's depth and the relative pose (pixels without depth: as points at
               // infinity)
  kReuse,      // the keyframe's label image as it is
};

const char* LabelPropagationName(LabelPropagation propagation);

// One keyframe's segmentation: its label image (CV_8UC1, ClassMap ids, the size of its left image) and the
// pose of its left camera. Immutable once made; shared by the frames that take their labels from it.
struct KeyframeLabels {
  std::int64_t frame_id = -1;
  std::optional<Pose3d> world_from_cam;
  cv::Mat labels;
};

// Which frames are keyframes, decided in stream order: the first frame, then the first frame whose id is at
// least `every_frames` after the last keyframe's. A frame without a pose is always a keyframe (labels cannot
// be carried to or from it), and so is the frame after it, and a frame whose id is lower than the last
// keyframe's (a sequence that starts over). The decision depends only on the ids and poses seen, never on
// timing. Not thread-safe (the pipeline's reader thread owns it).
class KeyframeSchedule {
 public:
  // every_frames >= 1 (1 = every frame is a keyframe).
  explicit KeyframeSchedule(int every_frames);
  // Whether the frame `frame_id` should be a keyframe, given the keyframes recorded so far.
  bool IsDue(std::int64_t frame_id, bool has_pose) const;
  // `frame_id` became a keyframe (a due frame may be refused, e.g. when the segmenter's queue is full in
  // realtime mode: the next frame is then due).
  void Record(std::int64_t frame_id, bool has_pose);
  // Changes the interval from the next IsDue() on (every_frames >= 1).
  void SetEveryFrames(int every_frames);

 private:
  int every_frames_;
  std::optional<std::int64_t> last_id_;
  bool last_has_pose_ = false;
};

struct PropagationReport {
  std::int64_t with_depth = 0;   // pixels lifted with their own depth
  std::int64_t at_infinity = 0;  // pixels without depth, reprojected as points at infinity (rotation only)
  std::int64_t outside = 0;  // pixels that land outside the keyframe's image or behind it (→ unlabelled)
};

// The labels of a frame whose left camera is at `world_from_cam`, carried from `keyframe` (same camera
// intrinsics, same image size) by reprojection: pixel (u, v) with depth z = depth_m(v, u) > 0 (finite) is the
// point z·K⁻¹(u, v, 1) of the frame's camera; a pixel without depth (0, negative, NaN or infinite) is the
// direction K⁻¹(u, v, 1) at infinity, moved by the rotation only. The point is projected into the keyframe's
// camera and takes the label of the nearest pixel (integer coordinates are pixel centres); a point outside
// the keyframe's image or not in front of its camera is `unlabelled_id`. No occlusion test: a point hidden
// from the keyframe by a nearer surface takes that surface's label.
// Requires: labels CV_8UC1 of intrinsics' size, depth_m CV_32F of the same size, both poses (programmer
// errors otherwise).
cv::Mat PropagateLabels(const KeyframeLabels& keyframe, const Pose3d& world_from_cam, const cv::Mat& depth_m,
                        const StereoCalibration& intrinsics, Label unlabelled_id,
                        PropagationReport* report = nullptr);

}  // namespace semap
