// Conversions between semap's engine types and the LCM messages of io/lcm/types/.
#pragma once

#include <cstdint>

#include "engine/core/calibration.h"
#include "engine/core/mesh_delta.h"
#include "engine/pipeline/frame_stats.h"
#include "semap_lcm/camera_pose_t.hpp"
#include "semap_lcm/frame_stats_t.hpp"
#include "semap_lcm/mesh_delta_t.hpp"
#include "semap_lcm/mesh_snapshot_t.hpp"

namespace semap::io {

// Microseconds since the Unix epoch, now.
std::int64_t NowUtime();

semap_lcm::mesh_delta_t ToLcmDelta(const MeshDelta& delta, std::int64_t sequence, std::int64_t utime);
semap_lcm::mesh_snapshot_t ToLcmSnapshot(const MeshDelta& snapshot, std::int64_t sequence, std::int64_t utime);
semap_lcm::frame_stats_t ToLcm(const FrameStats& stats, std::int64_t utime);
semap_lcm::camera_pose_t ToLcmPose(std::int64_t frame_id, double timestamp_s, const Pose3d& world_from_cam,
                                   std::int64_t utime);

// Decoded messages as engine deltas (a snapshot is a delta to apply after a reset). Positions are floats
// on the wire. Throws std::runtime_error if the message's arrays are inconsistent.
MeshDelta FromLcm(const semap_lcm::mesh_delta_t& msg);
MeshDelta FromLcm(const semap_lcm::mesh_snapshot_t& msg);

}  // namespace semap::io
