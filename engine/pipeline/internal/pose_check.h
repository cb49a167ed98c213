// Whether a frame's pose can go into the map: the reader thread's check of each frame's pose.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>

#include "engine/core/frame.h"

namespace semap::pipeline_internal {

// The last frame whose pose went into the map.
struct AcceptedPose {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  Eigen::Vector3d position;
};

// Why `pose` cannot go into the map, or "" when it can: non-finite entries, a linear part that is not a
// rotation, or (against the last accepted frame `last`) a speed above `max_speed_mps` (0 = no speed check).
// The time between the frames is taken as at least `min_frame_period_s`, so that repeated time stamps do not
// reject every frame.
std::string PoseProblem(const Pose3d& pose, double timestamp_s, const std::optional<AcceptedPose>& last,
                        double max_speed_mps, double min_frame_period_s);

}  // namespace semap::pipeline_internal
