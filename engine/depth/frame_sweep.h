// Depth of a frame without a stereo pair: its left image swept against the frame's neighbour views
// (Frame::neighbour_views), handed on in the stereo path's form so that the cloud, the depth view and the
// map's uncertainty treat it as they treat SGBM's.
#pragma once

#include "engine/core/frame.h"
#include "engine/depth/plane_sweep.h"
#include "engine/depth/stereo_depth.h"

namespace semap {

// The camera of `frame` as a view without pixels: its intrinsics as K, its pose (identity without one).
PlaneSweepView FrameCamera(const Frame& frame);

// The reference view of `frame` for the plane sweep: its left image in grey, its intrinsics as K, its pose;
// resampled by `scale` (0.5: half resolution, the pixel centres kept in place).
PlaneSweepView ReferenceView(const Frame& frame, double scale);

// A neighbour view resampled by `scale` as ReferenceView is.
PlaneSweepView ScaledView(const CalibratedView& view, double scale);

// The plane-sweep depth of `frame` against its neighbour views, at half resolution when `half_resolution`
// (brought back to full resolution by nearest neighbour), as the disparity f·B / z that a rig of the frame's
// baseline (calibration.baseline_m) would measure; confidence 1 where the sweep gave a depth, 0 elsewhere
// (the sweep's own cost and confidence thresholds have dropped the unreliable pixels). Throws
// std::invalid_argument naming the frame when it has no neighbour views, no pose, or a calibration
// without a positive baseline, and what PlaneSweepDepth::Compute throws.
// `directions`: the sweep directions besides the fronto-parallel planes (PlaneSweepDepth::Compute).
DisparityResult SweepFrameDisparity(const Frame& frame, const PlaneSweepDepth& sweep, bool half_resolution,
                                    const std::vector<SweepDirection>& directions = {});

}  // namespace semap
