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
#include "engine/pipeline/frame_stats.h"

namespace lcm {
class LCM;
}

namespace semap::io {

struct LcmOptions {
  // Publish over LCM at all (`semap run --lcm-url` turns it on).
  bool enabled = false;
  // LCM provider URL; ttl=0 keeps the multicast on this host.
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  // Channel names are <prefix>MESH_SNAPSHOT, MESH_DELTA, FRAME_STATS, CAMERA_POSE.
  std::string channel_prefix = "SEMAP_";
  // The first mesh message is a snapshot; with N > 0 a full snapshot follows every N mesh messages so that
  // late subscribers can join, at the cost of keeping the whole published mesh in memory (it grows with the
  // drive). 0 = first only (bounded memory: the soak setting).
  int snapshot_every = 0;
  // Stats/pose messages waiting to be sent at most; further ones are dropped and counted.
  int queue_capacity = 64;

  void Check() const;
};

// The LCM URL could not be opened.
class LcmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thread-safe: every Publish* may be called from any thread and returns at once. Mesh deltas are never
// dropped: while the sender thread is busy they are coalesced into one pending delta (bounded by the mesh
// size). Stats and poses go through a bounded queue; when it is full the message is dropped and counted.
// Send failures (no route, socket error) are counted, never thrown.
class LcmPublisher {
 public:
  struct Counters {
    std::int64_t mesh_messages = 0;  // snapshots + deltas sent
    std::int64_t other_messages = 0; // stats + poses sent
    std::int64_t send_failures = 0;
    std::int64_t dropped = 0;        // stats/poses dropped on a full queue
  };

  // Throws LcmError naming the URL when LCM cannot be initialised with it.
  explicit LcmPublisher(const LcmOptions& options);
  // Sends everything still pending, then stops the thread.
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
  void SendMesh(PendingMesh& pending);

  LcmOptions options_;
  std::unique_ptr<lcm::LCM> lcm_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  std::unique_ptr<PendingMesh> pending_mesh_;  // guarded by mutex_
  std::deque<std::function<int(lcm::LCM&)>> queue_;  // guarded by mutex_
  bool busy_ = false;
  bool stop_ = false;
  Counters counters_;
  // Sender-thread state.
  MeshAccumulator sent_;
  std::int64_t sequence_ = 0;
  std::thread thread_;
};

}  // namespace semap::io
