// Depth of a stereo frame from SGBM and the plane sweep together, as the paper combines them: the left image
// is swept against its right image and the left images of earlier frames (their poses from the sequence or
// the odometry), and the sweep's depth is taken where its views' parallax beats the pair's. A far surface
// gets only the rig's baseline (KITTI: 0.54 m) from the pair, while the car moves about 1 m a frame: an
// earlier frame sees it with a longer baseline, the more so the farther its pixel lies from the direction of
// travel. Near that direction (the image centre on a straight drive) the earlier frames give no parallax and
// SGBM keeps the pixel.
#pragma once

#include <cstdint>
#include <deque>
#include <opencv2/core.hpp>

#include "engine/core/frame.h"
#include "engine/depth/plane_sweep.h"
#include "engine/depth/stereo_depth.h"

namespace semap {

// The frame's right image as a calibrated view: grey, the left camera's intrinsics, the left camera's pose
// moved by calibration.baseline_m along its x axis (a rectified pair).
CalibratedView RightView(const Frame& frame);

// Hands each stereo frame its right view and the left views of the `past_frames` frames before it, as
// neighbour views (the right view first, then the earlier frames, the nearest in time first), and keeps the
// frame's own left view for the frames after it. A frame without a right image or a pose is left alone and
// not kept. Not thread-safe: one reader thread calls Attach, in frame order.
class PastFrameViews {
 public:
  explicit PastFrameViews(int past_frames);
  void Attach(Frame* frame);

 private:
  int past_frames_;
  std::deque<CalibratedView> views_;  // the latest first
};

// Per pixel of the frame's left image, how far its ray's image moves in the neighbour views per unit of
// inverse depth, at the inverse depth `inverse_depth_per_m` of that pixel (CV_32F, m⁻¹; 0: at infinity): for
// each neighbour, |∂(u, v)/∂(1/z)| in px·m, and of those the mean of the `best_views` largest (0: of all),
// as the sweep's aggregation keeps its best views. The rectified pair's own parallax is f·B everywhere. The
// result is CV_32F, the left image's size.
cv::Mat SweepParallax(const Frame& frame, const cv::Mat& inverse_depth_per_m, int best_views);

// What CombineStereoAndSweep did with the frame's pixels.
struct StereoSweepCounts {
  std::int64_t sgbm = 0;      // SGBM's disparity kept
  std::int64_t replaced = 0;  // SGBM's disparity replaced by the sweep's
  void Add(const StereoSweepCounts& o) {
    sgbm += o.sgbm;
    replaced += o.replaced;
  }
};

// Per pixel of SGBM's disparity, SGBM's or the sweep's (the sweep's depth z as the pair's measured disparity
// f·B / z − frame.disparity_offset, so that the cloud treats both alike). The sweep's is taken where it has a
// depth, its parallax (SweepParallax at its own depth, over options.best_views) is at least
// stereo_parallax_gain · f·B, SGBM's depth is at least stereo_min_depth_m, and the two disparities differ by
// at most stereo_max_disagreement_px; it then has confidence 1 (matched). A pixel without an SGBM disparity
// stays without: where SGBM found nothing the sweep's depths (all within its far range) filled near surfaces
// wrongly. `sgbm` and `swept` are the left image's size, in full-resolution px (SweepFrameDisparity gives the
// sweep's in that form).
DisparityResult CombineStereoAndSweep(const Frame& frame, const DisparityResult& sgbm,
                                      const DisparityResult& swept, const PlaneSweepOptions& options,
                                      StereoSweepCounts* counts = nullptr);

// The sweep's options for stereo frames: the depth range [stereo_min_depth_m, stereo_max_depth_m], the window
// stereo_window_px, the aggregation stereo_best_views, and no label directions (the second sweep serves
// frames without a pair).
PlaneSweepOptions StereoFrameSweepOptions(const PlaneSweepOptions& options);

// The disparity of a stereo frame: SGBM's on its pair, combined with the plane sweep's (`stereo_sweep`, built
// from StereoFrameSweepOptions) when the frame has neighbour views (PastFrameViews) beyond its right view.
// Throws what StereoDepth::Compute and SweepFrameDisparity throw.
DisparityResult StereoSweepDisparity(const Frame& frame, const StereoDepth& stereo,
                                     const PlaneSweepDepth& stereo_sweep,
                                     StereoSweepCounts* counts = nullptr);

}  // namespace semap
