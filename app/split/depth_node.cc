#include "app/split/depth_node.h"

#include <stdexcept>
#include <utility>

#include "engine/core/stopwatch.h"

namespace semap::app {

FrameShare ParseFrameShare(const std::string& text) {
  const size_t slash = text.find('/');
  FrameShare share;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    size_t used = 0;
    share.index = std::stoi(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("index");
    const std::string count = text.substr(slash + 1);
    share.count = std::stoi(count, &used);
    if (used != count.size()) throw std::invalid_argument("count");
  } catch (const std::exception&) {
    throw std::invalid_argument("frame share '" + text + "': expected I/N, e.g. 0/2");
  }
  if (share.count < 1 || share.index < 0 || share.index >= share.count) {
    throw std::invalid_argument("frame share '" + text + "': needs 0 <= I < N");
  }
  return share;
}

FrameShareReader::FrameShareReader(std::unique_ptr<FrameReader> source, FrameShare share)
    : source_(std::move(source)), share_(share) {}

std::optional<Frame> FrameShareReader::Next() {
  while (true) {
    std::optional<Frame> frame = source_->Next();
    if (!frame || share_.Takes(frame->id)) return frame;
  }
}

std::int64_t DepthConfigFingerprint(const Config& config) {
  Config parts;  // the defaults, but for what the depth, the labels and the cloud depend on
  parts.depth = config.depth;
  parts.plane_sweep = config.plane_sweep;
  parts.semantics = config.semantics;
  parts.input.class_map = config.input.class_map;
  // FNV-1a over the sections' YAML text: any value that differs changes it.
  constexpr std::uint64_t kOffset = 14695981039346656037ull, kPrime = 1099511628211ull;
  std::uint64_t h = kOffset;
  for (const unsigned char c : DumpConfig(parts)) h = (h ^ c) * kPrime;
  return static_cast<std::int64_t>(h);
}

DepthFramePublisher::DepthFramePublisher(const io::DepthFrameSender& sender, std::int64_t first_frame_id,
                                         std::int64_t sequence_frames, Send send)
    : sender_(sender),
      first_frame_id_(first_frame_id),
      sequence_frames_(sequence_frames),
      send_(std::move(send)) {}

void DepthFramePublisher::OnFrameDepth(const Frame& frame, const FrameDepth& depth) {
  io::DepthFrameMessage m;
  m.frame_id = frame.id;
  m.timestamp_s = frame.timestamp_s;
  m.sensed_unix_s = frame.sensed_unix_s;
  m.first_frame_id = first_frame_id_;
  m.sequence_frames = sequence_frames_;
  m.calibration = frame.calibration;
  m.world_from_cam = frame.world_from_cam;
  m.disparity_offset = frame.disparity_offset;
  m.left = frame.left;
  m.disparity_px = depth.disparity_px;
  m.confidence = depth.confidence;
  m.labels = depth.labels;
  const Stopwatch stopwatch;
  const std::vector<io::EncodedMessage> datagrams = sender_.Encode(m);
  const double encode_ms = stopwatch.ElapsedMs();
  std::lock_guard<std::mutex> lock(mutex_);
  for (const io::EncodedMessage& d : datagrams) {
    send_(d);
    counters_.bytes += static_cast<std::int64_t>(d.size());
  }
  ++counters_.frames;
  counters_.datagrams += static_cast<std::int64_t>(datagrams.size());
  counters_.encode_ms += encode_ms;
}

void DepthFramePublisher::PublishDropped(std::int64_t frame_id, double timestamp_s) {
  const io::EncodedMessage notice =
      sender_.EncodeDropped(frame_id, timestamp_s, first_frame_id_, sequence_frames_);
  std::lock_guard<std::mutex> lock(mutex_);
  send_(notice);
  ++counters_.notices;
  ++counters_.datagrams;
  counters_.bytes += static_cast<std::int64_t>(notice.size());
}

DepthFramePublisher::Counters DepthFramePublisher::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

}  // namespace semap::app
