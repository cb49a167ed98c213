#include "app/split/received_frames.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <utility>

#include "engine/core/stopwatch.h"

namespace semap::app {

namespace {
// How long the reader sleeps between looks at the received frames when nothing arrives (a wait or the end
// is noticed this late at most).
constexpr double kPollSliceS = 0.05;
}  // namespace

Frame FrameFromMessage(io::DepthFrameMessage message) {
  Frame f;
  f.id = message.frame_id;
  f.timestamp_s = message.timestamp_s;
  f.sensed_unix_s = message.sensed_unix_s;
  f.left = std::move(message.left);
  f.calibration = message.calibration;
  f.world_from_cam = message.world_from_cam;
  f.disparity_offset = message.disparity_offset;
  auto depth = std::make_shared<FrameDepth>();
  depth->disparity_px = std::move(message.disparity_px);
  depth->confidence = std::move(message.confidence);
  depth->labels = std::move(message.labels);
  f.depth = std::move(depth);
  return f;
}

ReceivedFrames::ReceivedFrames(const SplitOptions& options, std::int64_t config_fingerprint, double now_s)
    : options_(options), assembler_(options.run_id, config_fingerprint), started_s_(now_s) {}

void ReceivedFrames::Add(const void* data, size_t size, double now_s) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::int64_t parts_before = assembler_.counters().parts;
    const Stopwatch stopwatch;
    std::optional<io::DepthFrameMessage> whole = assembler_.Add(data, size);
    decode_ms_ += stopwatch.ElapsedMs();
    if (assembler_.counters().parts > parts_before) last_arrival_s_ = now_s;
    for (const std::int64_t id : assembler_.TakeDropped()) announced_.insert(id);
    ++datagrams_;
    if (whole) {
      ++frames_;
      if (!next_id_) {
        first_frame_id_ = whole->first_frame_id;
        end_id_ = whole->first_frame_id + whole->sequence_frames;
      }
      // Until the first frame is taken, the run starts at the lowest whole frame.
      if (!taken_any_ && (!next_id_ || whole->frame_id < *next_id_)) next_id_ = whole->frame_id;
      if (whole->frame_id < *next_id_ || ready_.count(whole->frame_id) > 0) {
        ++late_;
      } else {
        const std::int64_t id = whole->frame_id;
        ready_.emplace(id, FrameFromMessage(std::move(*whole)));
        ready_at_s_.emplace(id, now_s);
      }
    }
  }
  arrived_.notify_all();
}

double ReceivedFrames::EarliestReadyS(double now_s) const {
  double earliest_s = now_s;
  for (const auto& [id, at_s] : ready_at_s_) earliest_s = std::min(earliest_s, at_s);
  return earliest_s;
}

void ReceivedFrames::GiveUp(std::int64_t frame_id) {
  lost_.push_back({frame_id, 0.0});
  ++lost_count_;
  assembler_.DropBefore(frame_id + 1);
}

bool ReceivedFrames::Ended(double now_s) {
  if (!next_id_) return now_s - started_s_ >= options_.first_frame_timeout_s;
  if (*next_id_ >= end_id_) return true;
  if (!ready_.empty() || now_s - last_arrival_s_ < options_.idle_end_s) return false;
  for (; *next_id_ < end_id_; ++*next_id_) GiveUp(*next_id_);  // nothing more is coming
  return true;
}

ReceivedFrames::Next ReceivedFrames::Poll(double now_s, Frame* frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  while (next_id_ && *next_id_ < end_id_) {
    if (!taken_any_ && *next_id_ != first_frame_id_ && now_s - EarliestReadyS(now_s) < options_.wait_s) {
      break;  // a frame before the first one received may still be on its way from another depth node
    }
    if (auto it = ready_.find(*next_id_); it != ready_.end()) {
      taken_any_ = true;
      *frame = std::move(it->second);
      ready_.erase(it);
      ready_at_s_.erase(*next_id_);
      ++*next_id_;
      return Next::kFrame;
    }
    if (taken_any_ && announced_.erase(*next_id_) > 0) {
      GiveUp((*next_id_)++);  // its depth node said it will not come: no wait
      continue;
    }
    // Frames behind the missing one have arrived: it is late since the first of them did.
    if (ready_.empty() || now_s - EarliestReadyS(now_s) < options_.wait_s) break;
    GiveUp((*next_id_)++);
  }
  return Ended(now_s) ? Next::kEnd : Next::kWait;
}

void ReceivedFrames::WaitForData(double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  const std::uint64_t seen = datagrams_;
  arrived_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return datagrams_ != seen; });
}

std::vector<FrameReader::LostFrame> ReceivedFrames::TakeLost() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(lost_, {});
}

std::vector<std::string> ReceivedFrames::TakeRefusals() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> fresh = assembler_.TakeRefusals();
  refusals_.insert(refusals_.end(), fresh.begin(), fresh.end());
  return fresh;
}

std::vector<std::string> ReceivedFrames::Refusals() {
  TakeRefusals();
  std::lock_guard<std::mutex> lock(mutex_);
  return refusals_;
}

ReceivedFrames::Counters ReceivedFrames::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {assembler_.counters(), frames_, late_, lost_count_, decode_ms_};
}

ReceivedFrameReader::ReceivedFrameReader(std::shared_ptr<ReceivedFrames> frames, std::function<bool()> stop)
    : frames_(std::move(frames)), stop_(std::move(stop)) {}

std::optional<Frame> ReceivedFrameReader::Next() {
  Frame frame;
  while (true) {
    if (stop_ && stop_()) return std::nullopt;
    for (const std::string& r : frames_->TakeRefusals()) spdlog::warn("depth frames refused: {}", r);
    switch (frames_->Poll(clock_.NowS(), &frame)) {
      case ReceivedFrames::Next::kFrame:
        return frame;
      case ReceivedFrames::Next::kEnd:
        return std::nullopt;
      case ReceivedFrames::Next::kWait:
        frames_->WaitForData(kPollSliceS);
        break;
    }
  }
}

}  // namespace semap::app
