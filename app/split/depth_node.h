// The depth node's side of a split run: which frames this node computes, and how each frame's depth and
// labels leave it (encoded as depth-frame datagrams, handed to a transport).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "app/config/config.h"
#include "engine/pipeline/stages.h"
#include "io/lcm/depth_frames.h"

namespace semap::app {

// The frames of a sequence shared out among `count` depth nodes: node `index` computes the frames whose id
// is index modulo count.
struct FrameShare {
  int index = 0;
  int count = 1;
  bool Takes(std::int64_t frame_id) const { return frame_id % count == index; }
};

// Parses "I/N" (0 <= I < N): throws std::invalid_argument naming the text.
FrameShare ParseFrameShare(const std::string& text);

// The frames of `source` that `share` gives this node, in order (the others are read and passed over, so
// that readers before this one, such as the visual odometry, see every frame). Called from one thread.
class FrameShareReader : public FrameReader {
 public:
  FrameShareReader(std::unique_ptr<FrameReader> source, FrameShare share);
  std::optional<Frame> Next() override;

 private:
  std::unique_ptr<FrameReader> source_;
  FrameShare share_;
};

// A fingerprint of what a frame's depth, labels and cloud depend on in `config`: the depth, plane_sweep and
// semantics sections and input.class_map. A map node refuses the frames of a depth node whose fingerprint
// differs from its own.
std::int64_t DepthConfigFingerprint(const Config& config);

// Encodes each frame's depth (and its left image, calibration, pose and time stamps) and hands the
// datagrams to `send`, in order, one frame at a time. Thread-safe: the depth workers call it concurrently
// (each encodes on its own thread; sending is serialised).
class DepthFramePublisher : public FrameDepthSink {
 public:
  using Send = std::function<void(const io::EncodedMessage&)>;
  struct Counters {
    std::int64_t frames = 0;
    std::int64_t datagrams = 0;
    std::int64_t bytes = 0;
    double encode_ms = 0.0;    // summed over the frames
    std::int64_t notices = 0;  // drop notices sent
  };

  // `first_frame_id`, `sequence_frames`: the sequence as the node plays it (every node of a run alike).
  DepthFramePublisher(const io::DepthFrameSender& sender, std::int64_t first_frame_id,
                      std::int64_t sequence_frames, Send send);
  void OnFrameDepth(const Frame& frame, const FrameDepth& depth) override;
  // A drop notice for a frame of this node's share that it will not send (it fell behind, or the frame
  // failed here): the map node gives it up at once instead of waiting for it.
  void PublishDropped(std::int64_t frame_id, double timestamp_s);
  Counters counters() const;

 private:
  io::DepthFrameSender sender_;
  std::int64_t first_frame_id_;
  std::int64_t sequence_frames_;
  Send send_;
  mutable std::mutex mutex_;  // serialises send_ and guards counters_
  Counters counters_;
};

// The depth node's pipeline sink: each frame the node drops (behind, in realtime mode) or that fails here
// becomes a drop notice (DepthFramePublisher::PublishDropped). Called from the pipeline's output thread.
class DropNoticeSink : public PipelineSink {
 public:
  explicit DropNoticeSink(DepthFramePublisher* publisher) : publisher_(publisher) {}
  void OnFrame(const FrameStats&, const MeshDelta&, const std::optional<Pose3d>&) override {}
  void OnFrameDropped(std::int64_t frame_id, double timestamp_s, const std::string&) override {
    publisher_->PublishDropped(frame_id, timestamp_s);
  }
  void OnFrameError(std::int64_t frame_id, const std::string&, const std::string&) override {
    publisher_->PublishDropped(frame_id, 0.0);
  }

 private:
  DepthFramePublisher* publisher_;
};

}  // namespace semap::app
