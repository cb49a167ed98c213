#include "io/lcm/lcm_publisher.h"

#include <lcm/lcm-cpp.hpp>

#include "engine/core/check.h"
#include "io/lcm/lcm_codec.h"

namespace semap::io {

void LcmOptions::Check() const {
  SEMAP_CHECK_OPTION(!url.empty(), "url", "''", "must not be empty");
  SEMAP_CHECK_OPTION(snapshot_every >= 0, "snapshot_every", snapshot_every, "must be >= 0 (0 = first only)");
  SEMAP_CHECK_OPTION(queue_capacity >= 1, "queue_capacity", queue_capacity, "must be >= 1");
}

// Deltas composed while the sender was busy: later removals cancel earlier additions.
struct LcmPublisher::PendingMesh {
  std::int64_t frame_id = -1;
  std::vector<TriangleId> removed;
  std::unordered_map<TriangleId, std::array<VertexId, 3>> added;
  MeshDelta vertex_store;

  void Compose(const MeshDelta& d) {
    frame_id = d.frame_id;
    for (auto id : d.removed_triangle_ids) {
      if (added.erase(id) == 0) removed.push_back(id);
    }
    for (size_t i = 0; i < d.added_triangle_ids.size(); ++i) added[d.added_triangle_ids[i]] = d.added_triangles[i];
    for (size_t i = 0; i < d.vertex_ids.size(); ++i) {
      vertex_store.vertex_ids.push_back(d.vertex_ids[i]);
      vertex_store.vertex_positions.push_back(d.vertex_positions[i]);
      if (!d.vertex_colors_rgb.empty()) vertex_store.vertex_colors_rgb.push_back(d.vertex_colors_rgb[i]);
      if (!d.vertex_labels.empty()) vertex_store.vertex_labels.push_back(d.vertex_labels[i]);
    }
  }

  // The composed delta, with only the vertices that the remaining additions reference.
  MeshDelta ToDelta() const {
    MeshDelta out;
    out.frame_id = frame_id;
    out.removed_triangle_ids = removed;
    std::unordered_map<VertexId, size_t> wanted;
    for (const auto& [id, t] : added) {
      out.added_triangle_ids.push_back(id);
      out.added_triangles.push_back(t);
      for (auto v : t) wanted.emplace(v, 0);
    }
    const bool colors = vertex_store.vertex_colors_rgb.size() == vertex_store.vertex_ids.size();
    const bool labels = vertex_store.vertex_labels.size() == vertex_store.vertex_ids.size();
    // The last upsert of a vertex wins, as in MeshAccumulator.
    for (size_t i = vertex_store.vertex_ids.size(); i-- > 0;) {
      auto it = wanted.find(vertex_store.vertex_ids[i]);
      if (it == wanted.end() || it->second == 1) continue;
      it->second = 1;
      out.vertex_ids.push_back(vertex_store.vertex_ids[i]);
      out.vertex_positions.push_back(vertex_store.vertex_positions[i]);
      if (colors) out.vertex_colors_rgb.push_back(vertex_store.vertex_colors_rgb[i]);
      if (labels) out.vertex_labels.push_back(vertex_store.vertex_labels[i]);
    }
    return out;
  }
};

LcmPublisher::LcmPublisher(const LcmOptions& options) : options_(options) {
  options_.Check();
  lcm_ = std::make_unique<lcm::LCM>(options_.url);
  if (!lcm_->good()) throw LcmError("cannot open LCM URL '" + options_.url + "'");
  thread_ = std::thread([this] { Run(); });
}

LcmPublisher::~LcmPublisher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LcmPublisher::PublishMeshDelta(const MeshDelta& delta) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pending_mesh_) pending_mesh_ = std::make_unique<PendingMesh>();
    pending_mesh_->Compose(delta);
  }
  wake_.notify_one();
}

void LcmPublisher::PublishFrameStats(const FrameStats& stats) {
  auto msg = ToLcm(stats, NowUtime());
  const std::string channel = options_.channel_prefix + "FRAME_STATS";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(queue_.size()) >= options_.queue_capacity) {
      ++counters_.dropped;
      return;
    }
    queue_.push_back([msg, channel](lcm::LCM& l) { return l.publish(channel, &msg); });
  }
  wake_.notify_one();
}

void LcmPublisher::PublishCameraPose(std::int64_t frame_id, double timestamp_s, const Pose3d& world_from_cam) {
  auto msg = ToLcmPose(frame_id, timestamp_s, world_from_cam, NowUtime());
  const std::string channel = options_.channel_prefix + "CAMERA_POSE";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(queue_.size()) >= options_.queue_capacity) {
      ++counters_.dropped;
      return;
    }
    queue_.push_back([msg, channel](lcm::LCM& l) { return l.publish(channel, &msg); });
  }
  wake_.notify_one();
}

void LcmPublisher::Flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return !busy_ && !pending_mesh_ && queue_.empty(); });
}

LcmPublisher::Counters LcmPublisher::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

void LcmPublisher::SendMesh(PendingMesh& pending) {
  const MeshDelta delta = pending.ToDelta();
  // The first mesh message is a snapshot; then one every snapshot_every messages when enabled. Only then
  // does the sender keep the whole published mesh (it grows with the map, finalised parts included).
  const bool keep_all = options_.snapshot_every > 0;
  if (keep_all) sent_.Apply(delta);
  int rc = 0;
  const bool snapshot = sequence_ == 0 || (keep_all && sequence_ % options_.snapshot_every == 0);
  if (snapshot) {
    const auto msg = ToLcmSnapshot(keep_all ? sent_.AsSnapshot(delta.frame_id) : delta, sequence_, NowUtime());
    rc = lcm_->publish(options_.channel_prefix + "MESH_SNAPSHOT", &msg);
  } else {
    const auto msg = ToLcmDelta(delta, sequence_, NowUtime());
    rc = lcm_->publish(options_.channel_prefix + "MESH_DELTA", &msg);
  }
  ++sequence_;
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.mesh_messages;
  if (rc != 0) ++counters_.send_failures;
}

void LcmPublisher::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stop_ || pending_mesh_ || !queue_.empty(); });
    if (!pending_mesh_ && queue_.empty()) break;  // stop_ with nothing left
    busy_ = true;
    std::unique_ptr<PendingMesh> mesh = std::move(pending_mesh_);
    std::deque<std::function<int(lcm::LCM&)>> batch;
    batch.swap(queue_);
    lock.unlock();
    if (mesh) SendMesh(*mesh);
    int failures = 0;
    for (auto& send : batch) failures += send(*lcm_) != 0 ? 1 : 0;
    lock.lock();
    counters_.other_messages += static_cast<std::int64_t>(batch.size());
    counters_.send_failures += failures;
    busy_ = false;
    idle_.notify_all();
  }
  busy_ = false;
  idle_.notify_all();
}

}  // namespace semap::io
