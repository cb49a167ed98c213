#include "io/lcm/lcm_codec.h"

#include <chrono>
#include <stdexcept>

namespace semap::io {
namespace {

// Fills the vertex and added-triangle arrays shared by snapshots and deltas.
template <typename Msg>
void FillMesh(const MeshDelta& d, Msg* m) {
  m->num_vertices = static_cast<std::int32_t>(d.vertex_ids.size());
  m->vertex_ids.assign(d.vertex_ids.begin(), d.vertex_ids.end());
  m->positions.resize(d.vertex_ids.size());
  m->colors.resize(d.vertex_ids.size());
  m->labels.resize(d.vertex_ids.size());
  for (size_t i = 0; i < d.vertex_ids.size(); ++i) {
    const auto& p = d.vertex_positions[i];
    m->positions[i] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
    const auto c = d.vertex_colors_rgb.empty() ? std::array<std::uint8_t, 3>{200, 200, 200} : d.vertex_colors_rgb[i];
    m->colors[i] = {c[0], c[1], c[2]};
    m->labels[i] = d.vertex_labels.empty() ? 0 : d.vertex_labels[i];
  }
  m->num_triangles = static_cast<std::int32_t>(d.added_triangle_ids.size());
  m->triangle_ids.assign(d.added_triangle_ids.begin(), d.added_triangle_ids.end());
  m->triangles.resize(d.added_triangles.size());
  for (size_t i = 0; i < d.added_triangles.size(); ++i) {
    const auto& t = d.added_triangles[i];
    m->triangles[i] = {static_cast<std::int64_t>(t[0]), static_cast<std::int64_t>(t[1]),
                       static_cast<std::int64_t>(t[2])};
  }
}

template <typename Msg>
MeshDelta ReadMesh(const Msg& m) {
  if (m.num_vertices < 0 || m.num_triangles < 0 || m.vertex_ids.size() != size_t(m.num_vertices) ||
      m.positions.size() != size_t(m.num_vertices) || m.triangle_ids.size() != size_t(m.num_triangles) ||
      m.triangles.size() != size_t(m.num_triangles)) {
    throw std::runtime_error("mesh message with inconsistent array sizes");
  }
  MeshDelta d;
  d.frame_id = m.frame_id;
  for (std::int32_t i = 0; i < m.num_vertices; ++i) {
    d.vertex_ids.push_back(static_cast<VertexId>(m.vertex_ids[i]));
    d.vertex_positions.emplace_back(m.positions[i][0], m.positions[i][1], m.positions[i][2]);
    d.vertex_colors_rgb.push_back({static_cast<std::uint8_t>(m.colors[i][0]),
                                   static_cast<std::uint8_t>(m.colors[i][1]),
                                   static_cast<std::uint8_t>(m.colors[i][2])});
    d.vertex_labels.push_back(static_cast<Label>(m.labels[i]));
  }
  for (std::int32_t i = 0; i < m.num_triangles; ++i) {
    d.added_triangle_ids.push_back(static_cast<TriangleId>(m.triangle_ids[i]));
    d.added_triangles.push_back({static_cast<VertexId>(m.triangles[i][0]), static_cast<VertexId>(m.triangles[i][1]),
                                 static_cast<VertexId>(m.triangles[i][2])});
  }
  return d;
}

}  // namespace

std::int64_t NowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

semap_lcm::mesh_delta_t ToLcmDelta(const MeshDelta& delta, std::int64_t sequence, std::int64_t utime) {
  semap_lcm::mesh_delta_t m;
  m.utime = utime;
  m.frame_id = delta.frame_id;
  m.sequence = sequence;
  m.num_removed = static_cast<std::int32_t>(delta.removed_triangle_ids.size());
  m.removed_triangle_ids.assign(delta.removed_triangle_ids.begin(), delta.removed_triangle_ids.end());
  FillMesh(delta, &m);
  return m;
}

semap_lcm::mesh_snapshot_t ToLcmSnapshot(const MeshDelta& snapshot, std::int64_t sequence, std::int64_t utime) {
  semap_lcm::mesh_snapshot_t m;
  m.utime = utime;
  m.frame_id = snapshot.frame_id;
  m.sequence = sequence;
  FillMesh(snapshot, &m);
  return m;
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

MeshDelta FromLcm(const semap_lcm::mesh_delta_t& msg) {
  if (msg.num_removed < 0 || msg.removed_triangle_ids.size() != size_t(msg.num_removed)) {
    throw std::runtime_error("mesh delta with inconsistent removal list");
  }
  MeshDelta d = ReadMesh(msg);
  for (auto id : msg.removed_triangle_ids) d.removed_triangle_ids.push_back(static_cast<TriangleId>(id));
  return d;
}

MeshDelta FromLcm(const semap_lcm::mesh_snapshot_t& msg) { return ReadMesh(msg); }

}  // namespace semap::io
