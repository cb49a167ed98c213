// Publishes meshes, frame stats and camera poses over LCM from its own thread, so that publishing never
// blocks the map stage.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>

#include "engine/core/calibration.h"
#include "engine/core/mesh_delta.h"
#include "engine/core/options.h"
#include "engine/pipeline/frame_stats.h"
#include "io/lcm/mesh_blocks.h"

namespace lcm {
class LCM;
}

namespace semap::io {

struct LcmOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  bool enabled = false;
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string channel_prefix = "SEMAP_";
  double block_size_m = 4.0;
  int max_message_bytes = 60000;
  double resend_bytes_per_s = 1.0e6;
  double max_bytes_per_s = 8.0e6;
  int closing_rounds = 2;
  double closing_max_s = 30.0;
  int queue_capacity = 64;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("enabled", &enabled,
            "publish meshes, frame stats and poses over LCM (semap run --lcm-url turns it on)");
    v.Field("url", &url, "LCM provider URL; ttl=0 keeps multicast on this host", NotEmpty());
    v.Field("channel_prefix", &channel_prefix,
            "channel prefix: <prefix>MESH_BLOCK, MESH_END, FRAME_STATS, CAMERA_POSE");
    v.Field("block_size_m", &block_size_m,
            "edge of the cubic cells that cut the mesh into blocks (a triangle goes to its centroid's cell), "
            "metres",
            In(0.05, 1e4));
    v.Field("max_message_bytes", &max_message_bytes,
            "bound on every mesh message, bytes encoded; larger blocks go in parts (<= ~65000: one UDP "
            "datagram each, so one lost datagram loses one part only)",
            In(1024, 1 << 24));
    v.Field("resend_bytes_per_s", &resend_bytes_per_s,
            "budget of the round-robin re-send of block states and of the closing rounds, bytes/s (late "
            "subscribers converge in about mesh bytes / budget)",
            AtLeast(1000));
    // A stock kernel's socket buffer holds about three full messages.
    v.Field("max_bytes_per_s", &max_bytes_per_s,
            "ceiling on all mesh traffic (changes and re-sends), bytes/s, at least resend_bytes_per_s: "
            "messages are spaced so that a subscriber's socket buffer keeps up; changes published meanwhile "
            "are coalesced, never dropped");
    // What a late or lossy subscriber needs to complete the mesh.
    v.Field("closing_rounds", &closing_rounds,
            "re-send rounds over every block at the end of the run (within the budget), each followed by the "
            "block index, before the run's last message",
            In(0, 100));
    v.Field("closing_max_s", &closing_max_s,
            "at most this long for the closing rounds, s; the run's last message is sent anyway", AtLeast(0));
    v.Field("queue_capacity", &queue_capacity,
            "stats/pose messages queued at most; more are dropped and counted", AtLeast(1));
  }

  void Check() const;
};

// The LCM URL could not be opened.
class LcmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thread-safe: every Publish* may be called from any thread and returns at once. Mesh deltas are never
// dropped: while the sender thread is busy they are coalesced into one pending delta (bounded by the mesh
// size); the sender cuts them into block messages (io/lcm/mesh_blocks.h) and, when idle, re-sends block
// states round-robin within lcm.resend_bytes_per_s. Stats and poses go through a bounded queue; when it is
// full the message is dropped and counted. Send failures (no route, socket error) are counted, never thrown.
// Memory: the live triangles per block, plus the encoded finalised blocks (~40 bytes per finalised triangle).
class LcmPublisher {
 public:
  struct Counters {
    std::int64_t mesh_messages =
        0;  // block messages carrying changes (deltas, new versions, finalised blocks)
    std::int64_t resent_messages = 0;  // block messages re-sent (steady and closing rounds)
    std::int64_t index_messages = 0;   // mesh_end_t messages
    std::int64_t mesh_bytes = 0;       // bytes of all mesh messages (block and index, re-sends included)
    std::int64_t largest_message = 0;  // bytes of the largest mesh message
    std::int64_t other_messages = 0;   // stats + poses sent
    std::int64_t send_failures = 0;
    std::int64_t dropped = 0;  // stats/poses dropped on a full queue
  };

  // Throws LcmError naming the URL when LCM cannot be initialised with it.
  explicit LcmPublisher(const LcmOptions& options);
  // Sends everything still pending, then the closing rounds and the run's last message; stops the thread.
  ~LcmPublisher();
  LcmPublisher(const LcmPublisher&) = delete;
  LcmPublisher& operator=(const LcmPublisher&) = delete;

  void PublishMeshDelta(const MeshDelta& delta);
  void PublishFrameStats(const FrameStats& stats);
  void PublishCameraPose(std::int64_t frame_id, double timestamp_s, const Pose3d& world_from_cam);
  // Blocks until everything published so far has been handed to LCM.
  void Flush();
  Counters counters() const;

 private:
  struct PendingMesh;
  void Run();
  // Sends one mesh message on `channel`; counts it in `c`.
  void SendMesh(const std::string& channel, const std::vector<std::uint8_t>& msg, Counters* c);
  // The closing rounds and the run's last message (sender thread, after stop).
  void Close(MeshBlockSender& blocks, Counters* c);
  void Merge(const Counters& c);  // adds sender-thread counts under mutex_

  LcmOptions options_;
  std::string block_channel_, end_channel_;
  std::unique_ptr<lcm::LCM> lcm_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  std::unique_ptr<PendingMesh> pending_mesh_;        // guarded by mutex_
  std::deque<std::function<int(lcm::LCM&)>> queue_;  // guarded by mutex_
  bool busy_ = false;                                // guarded by mutex_
  bool stop_ = false;                                // guarded by mutex_
  Counters counters_;                                // guarded by mutex_
  std::thread thread_;
};

}  // namespace semap::io
