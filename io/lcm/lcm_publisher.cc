#include "io/lcm/lcm_publisher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <sstream>
#include <thread>

#include "engine/core/check.h"
#include "io/lcm/lcm_codec.h"

namespace semap::io {
namespace {

using Clock = std::chrono::steady_clock;

// Spaces messages so that they leave at `bytes_per_s` at most; an idle spell saves up no burst.
class Pacer {
 public:
  explicit Pacer(double bytes_per_s) : bytes_per_s_(bytes_per_s) {}
  bool Ready(Clock::time_point now) const { return now >= next_; }
  Clock::time_point next() const { return next_; }
  // Books a message of `bytes` sent now.
  void Book(size_t bytes, Clock::time_point now) {
    next_ = std::max(next_, now) + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(double(bytes) / bytes_per_s_));
  }
  // Waits until a message may go, then books it.
  void Wait(size_t bytes) {
    std::this_thread::sleep_until(next_);
    Book(bytes, Clock::now());
  }

 private:
  double bytes_per_s_;
  Clock::time_point next_ = Clock::now();
};

}  // namespace

void LcmOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (max_bytes_per_s < resend_bytes_per_s) {
    std::ostringstream bound;
    bound << "must be >= " << KeyOf(*this, resend_bytes_per_s) << " (" << resend_bytes_per_s << ")";
    throw OptionError(*this, max_bytes_per_s, bound.str());
  }
}

// Deltas composed while the sender was busy: later removals cancel earlier additions.
struct LcmPublisher::PendingMesh {
  std::int64_t frame_id = -1;
  std::vector<TriangleId> removed;
  std::vector<TriangleId> finalised;
  std::unordered_map<TriangleId, std::array<VertexId, 3>> added;
  MeshDelta vertex_store;

  void Compose(const MeshDelta& d) {
    frame_id = d.frame_id;
    finalised.insert(finalised.end(), d.finalised_triangle_ids.begin(), d.finalised_triangle_ids.end());
    for (auto id : d.removed_triangle_ids) {
      if (added.erase(id) == 0) removed.push_back(id);
    }
    for (size_t i = 0; i < d.added_triangle_ids.size(); ++i)
      added[d.added_triangle_ids[i]] = d.added_triangles[i];
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
    out.finalised_triangle_ids = finalised;
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

LcmPublisher::LcmPublisher(const LcmOptions& options)
    : options_(options),
      block_channel_(options.channel_prefix + "MESH_BLOCK"),
      end_channel_(options.channel_prefix + "MESH_END") {
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

void LcmPublisher::PublishCameraPose(std::int64_t frame_id, double timestamp_s,
                                     const Pose3d& world_from_cam) {
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

void LcmPublisher::SendMesh(const std::string& channel, const std::vector<std::uint8_t>& msg, Counters* c) {
  const int rc = lcm_->publish(channel, msg.data(), static_cast<unsigned int>(msg.size()));
  c->mesh_bytes += static_cast<std::int64_t>(msg.size());
  c->largest_message = std::max(c->largest_message, static_cast<std::int64_t>(msg.size()));
  if (rc != 0) ++c->send_failures;
}

void LcmPublisher::Merge(const Counters& c) {
  counters_.mesh_messages += c.mesh_messages;
  counters_.resent_messages += c.resent_messages;
  counters_.index_messages += c.index_messages;
  counters_.mesh_bytes += c.mesh_bytes;
  counters_.largest_message = std::max(counters_.largest_message, c.largest_message);
  counters_.other_messages += c.other_messages;
  counters_.send_failures += c.send_failures;
}

void LcmPublisher::Close(MeshBlockSender& blocks, Counters* c) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(options_.closing_max_s));
  Pacer pacer(std::min(options_.resend_bytes_per_s, options_.max_bytes_per_s));
  const auto send = [&](const std::string& channel, const std::vector<std::uint8_t>& msg) {
    pacer.Wait(msg.size());
    SendMesh(channel, msg, c);
  };
  for (int round = 0; round < options_.closing_rounds && blocks.num_blocks() > 0; ++round) {
    blocks.RestartResend();
    bool end_of_round = false;
    while (!end_of_round && Clock::now() < deadline) {
      send(block_channel_, *blocks.NextResend(&end_of_round));
      ++c->resent_messages;
    }
    if (!end_of_round || round + 1 == options_.closing_rounds) break;  // the last message follows
    for (const auto& msg : blocks.Index(options_.closing_rounds - 1 - round)) {
      send(end_channel_, msg);
      ++c->index_messages;
    }
  }
  for (const auto& msg : blocks.Index(0)) {  // the run's last message(s)
    send(end_channel_, msg);
    ++c->index_messages;
  }
}

void LcmPublisher::Run() {
  MeshBlockSender blocks(
      options_.block_size_m, options_.max_message_bytes,
      static_cast<std::int64_t>((std::uint64_t(std::random_device{}()) << 32) ^ std::random_device{}()));
  Pacer link(options_.max_bytes_per_s);       // every mesh message
  Pacer resend(options_.resend_bytes_per_s);  // the steady re-sends
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    const auto ready = [this] { return stop_ || pending_mesh_ || !queue_.empty(); };
    if (blocks.num_blocks() > 0) {
      wake_.wait_until(lock, std::max(resend.next(), link.next()), ready);
    } else {
      wake_.wait(lock, ready);
    }
    if (stop_ && !pending_mesh_ && queue_.empty()) break;
    busy_ = true;
    std::unique_ptr<PendingMesh> mesh = std::move(pending_mesh_);
    std::deque<std::function<int(lcm::LCM&)>> batch;
    batch.swap(queue_);
    lock.unlock();
    Counters c;
    for (auto& send : batch) c.send_failures += send(*lcm_) != 0 ? 1 : 0;
    c.other_messages += static_cast<std::int64_t>(batch.size());
    if (mesh) {
      // Spaced at lcm.max_bytes_per_s: deltas published meanwhile coalesce in pending_mesh_.
      for (const auto& msg : blocks.Apply(mesh->ToDelta())) {
        link.Wait(msg.size());
        SendMesh(block_channel_, msg, &c);
        ++c.mesh_messages;
      }
    }
    // The steady re-send: one message whenever both budgets allow (no catching up after a busy spell).
    const auto now = Clock::now();
    if (blocks.num_blocks() > 0 && resend.Ready(now) && link.Ready(now)) {
      bool end_of_round = false;
      std::vector<std::vector<std::uint8_t>> out{*blocks.NextResend(&end_of_round)};
      ++c.resent_messages;
      if (end_of_round) {
        for (auto& msg : blocks.Index(-1)) out.push_back(std::move(msg));
        c.index_messages += static_cast<std::int64_t>(out.size()) - 1;
      }
      for (size_t i = 0; i < out.size(); ++i) {
        SendMesh(i == 0 ? block_channel_ : end_channel_, out[i], &c);
        resend.Book(out[i].size(), now);
        link.Book(out[i].size(), now);
      }
    }
    lock.lock();
    Merge(c);
    busy_ = false;
    idle_.notify_all();
  }
  lock.unlock();
  Counters c;
  Close(blocks, &c);
  lock.lock();
  Merge(c);
  busy_ = false;
  idle_.notify_all();
}

}  // namespace semap::io
