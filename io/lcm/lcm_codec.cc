#include "io/lcm/lcm_codec.h"

#include <chrono>

namespace semap::io {

std::int64_t NowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

semap_lcm::frame_stats_t ToLcm(const FrameStats& s, std::int64_t utime) {
  semap_lcm::frame_stats_t m;
  m.utime = utime;
  m.frame_id = s.frame_id;
  m.frames_processed = s.frames_processed;
  m.frames_dropped = s.frames_dropped;
  m.frames_failed = s.frames_failed;
  m.fps = s.fps;
  m.num_stages = static_cast<std::int32_t>(s.stages.size());
  for (const auto& st : s.stages) {
    m.stage_names.push_back(st.name);
    m.stage_ms.push_back(st.last_ms);
    m.stage_p95_ms.push_back(st.p95_ms);
    m.queue_occupancy.push_back(st.queue_occupancy);
  }
  m.points_in = s.points_in;
  m.points_kept = s.points_kept;
  m.map_vertices = s.map_vertices;
  m.map_cells = s.map_cells;
  m.map_rays = s.map_rays;
  m.mesh_triangles = s.mesh_triangles;
  m.rss_mb = s.rss_mb;
  return m;
}

semap_lcm::camera_pose_t ToLcmPose(std::int64_t frame_id, double timestamp_s, const Pose3d& world_from_cam,
                                   std::int64_t utime) {
  semap_lcm::camera_pose_t m;
  m.utime = utime;
  m.frame_id = frame_id;
  m.timestamp_s = timestamp_s;
  const Eigen::Vector3d t = world_from_cam.translation();
  const Eigen::Quaterniond q(world_from_cam.rotation());
  m.position[0] = t.x();
  m.position[1] = t.y();
  m.position[2] = t.z();
  m.orientation[0] = q.w();
  m.orientation[1] = q.x();
  m.orientation[2] = q.y();
  m.orientation[3] = q.z();
  return m;
}

}  // namespace semap::io
