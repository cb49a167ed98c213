#include "io/frame_source.h"

#include <cmath>

#include "engine/core/check.h"

namespace semap::io {

const char* DatasetLayoutName(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kAuto:
      return "auto";
    case DatasetLayout::kKittiRaw:
      return "kitti_raw";
    case DatasetLayout::kKittiOdometry:
      return "kitti_odometry";
    case DatasetLayout::kKittiStereo2015:
      return "kitti_stereo2015";
    case DatasetLayout::kStrecha:
      return "strecha";
  }
  return "?";
}

void FrameSourceOptions::Check() const {
  SEMAP_CHECK_OPTION(first_frame >= 0, "first_frame", first_frame, "must be >= 0");
  SEMAP_CHECK_OPTION(max_frames >= 0, "max_frames", max_frames, "must be >= 0 (0 = all)");
  SEMAP_CHECK_OPTION(default_frame_period_s > 0.0 && std::isfinite(default_frame_period_s),
                     "default_frame_period_s", default_frame_period_s, "must be > 0");
  SEMAP_CHECK_OPTION(neighbour_views >= 1, "neighbour_views", neighbour_views, "must be >= 1");
  SEMAP_CHECK_OPTION(loops >= 1, "loops", loops, "must be >= 1");
  SEMAP_CHECK_OPTION(loop_gap_m >= 0.0 && std::isfinite(loop_gap_m), "loop_gap_m", loop_gap_m,
                     "must be >= 0");
}

}  // namespace semap::io
