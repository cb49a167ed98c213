// Which calibrated views a reference view's depth is swept against: the nearest cameras that look the same
// way, as a multi-view set's neighbours.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/core/calibration.h"

namespace semap {

struct ViewSelectionOptions {
  int max_views = 4;                 // at most this many neighbours
  double min_baseline_m = 1e-3;      // cameras nearer than this to the reference add no parallax: skipped
  double max_axis_angle_deg = 60.0;  // cameras whose optical axis turns further than this look elsewhere
};

// The indices into `candidates` of the reference's neighbours, nearest camera centre first: every
// candidate at least min_baseline_m from the reference whose optical axis (camera z) is within
// max_axis_angle_deg of the reference's, at most max_views of them (ties in distance: the lower index).
std::vector<std::size_t> SelectNeighbourViews(const Pose3d& world_from_reference,
                                              const std::vector<Pose3d>& world_from_candidates,
                                              const ViewSelectionOptions& options);

}  // namespace semap
