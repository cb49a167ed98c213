// Conversions between semap's engine types and the stats and pose LCM messages of io/lcm/types/.
#pragma once

#include <cstdint>

#include "engine/core/calibration.h"
#include "engine/pipeline/frame_stats.h"
#include "semap_lcm/camera_pose_t.hpp"
#include "semap_lcm/frame_stats_t.hpp"

namespace semap::io {

// Microseconds since the Unix epoch, now.
std::int64_t NowUtime();

semap_lcm::frame_stats_t ToLcm(const FrameStats& stats, std::int64_t utime);
semap_lcm::camera_pose_t ToLcmPose(std::int64_t frame_id, double timestamp_s, const Pose3d& world_from_cam,
                                   std::int64_t utime);

// Mesh messages: io/lcm/mesh_blocks.h.

}  // namespace semap::io
