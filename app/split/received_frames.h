// The map node's side of a split run: depth-frame datagrams in, from one or several depth nodes, in any
// order, some lost or repeated, some foreign or malformed; whole frames out, in frame order, each carrying
// its depth (Frame::depth), with the frames that never arrived whole counted as lost.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/split/split_options.h"
#include "engine/core/frame.h"
#include "engine/pipeline/clock.h"
#include "engine/pipeline/stages.h"
#include "io/lcm/depth_frames.h"

namespace semap::app {

// A whole received message as the frame the map node's pipeline reads: its id, time stamps, left image,
// calibration, pose and disparity offset, and its depth (Frame::depth); no right image.
Frame FrameFromMessage(io::DepthFrameMessage message);

// The frames a map node has received, and which comes next. Thread-safe: the LCM thread adds datagrams, the
// pipeline's reader takes frames. Time is passed in (seconds on any monotonic clock), so that a test decides
// when a wait has passed.
//
// Order: the lowest whole frame received starts the run (a map node started late begins there; earlier
// frames are not the run's): at once when it is the sequence's first frame, else once it has been whole for
// SplitOptions::wait_s (another depth node's earlier frame may still be on its way); from then on frames come
// out in id order up to the end of the sequence the depth nodes announce (DepthFrameMessage::first_frame_id +
// sequence_frames). A frame still missing when a later frame has been whole for SplitOptions::wait_s is lost;
// so is every frame still missing when nothing has arrived for SplitOptions::idle_end_s, which ends the run.
// A frame its depth node announced it will not send (a drop notice: the node was behind, or the frame failed
// there) is lost at once, without the wait.
class ReceivedFrames {
 public:
  struct Counters {
    io::DepthFrameAssembler::Counters
        parts;                // the assembler's: parts, duplicates, malformed, foreign, refused
    std::int64_t frames = 0;  // whole frames received
    std::int64_t late = 0;    // whole, but after their turn (before the start)
    std::int64_t lost = 0;    // given up
    double decode_ms = 0.0;   // the datagrams' checks, decompression and assembly, summed
  };
  // What Poll() found.
  enum class Next { kFrame, kWait, kEnd };

  // `config_fingerprint`: the map node's own (DepthConfigFingerprint); frames computed with another are
  // refused. `now_s`: when the node started listening (the first frame's timeout counts from there).
  ReceivedFrames(const SplitOptions& options, std::int64_t config_fingerprint, double now_s);

  // One datagram of the depth-frame channel, received at `now_s`.
  void Add(const void* data, size_t size, double now_s);

  // The next frame in order when it is there (kFrame, moved into `*frame`), kEnd once the sequence is done
  // or given up, kWait otherwise; frames given up meanwhile go to the lost list.
  Next Poll(double now_s, Frame* frame);
  // Blocks until a datagram arrives or `timeout_s` passes.
  void WaitForData(double timeout_s);

  // The frames given up since the last call, in id order.
  std::vector<FrameReader::LostFrame> TakeLost();
  // Why messages were refused (a depth node's configuration or calibration), once per node and reason.
  std::vector<std::string> TakeRefusals();
  // Every refusal so far, taken or not.
  std::vector<std::string> Refusals();
  Counters counters() const;

 private:
  void GiveUp(std::int64_t frame_id);
  // When the first of the frames waiting to be taken became whole (`now_s` when none waits).
  double EarliestReadyS(double now_s) const;
  bool Ended(double now_s);

  const SplitOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::uint64_t datagrams_ = 0;  // guarded by mutex_; arrived_'s predicate
  io::DepthFrameAssembler assembler_;
  std::map<std::int64_t, Frame> ready_;        // whole frames not yet taken, by id
  std::map<std::int64_t, double> ready_at_s_;  // when each of them became whole
  std::set<std::int64_t> announced_;           // frames a depth node said it will not send
  std::optional<std::int64_t> next_id_;        // the next frame in order; unset before the first whole one
  std::int64_t first_frame_id_ = 0;            // the sequence's first frame id
  std::int64_t end_id_ = 0;                    // one past the sequence's last frame id
  bool taken_any_ = false;                     // a frame has been taken: the start is fixed
  double started_s_;
  double last_arrival_s_ = 0.0;
  std::vector<FrameReader::LostFrame> lost_;
  std::vector<std::string> refusals_;  // taken so far
  std::int64_t frames_ = 0, late_ = 0, lost_count_ = 0;
  double decode_ms_ = 0.0;
};

// The pipeline's reader of a map node: the frames of `frames` in order (waiting for them on a steady clock),
// with the frames it gave up reported through TakeLost(). Refusals are logged as they are found. The
// sequence ends early, within a poll slice, once `stop` (when given) says so: a stopped run does not wait
// for frames.
class ReceivedFrameReader : public FrameReader {
 public:
  explicit ReceivedFrameReader(std::shared_ptr<ReceivedFrames> frames, std::function<bool()> stop = {});
  std::optional<Frame> Next() override;
  std::vector<LostFrame> TakeLost() override { return frames_->TakeLost(); }

 private:
  std::shared_ptr<ReceivedFrames> frames_;
  std::function<bool()> stop_;
  SteadyClock clock_;  // the time base of `frames_` (SteadyClock::NowS)
};

}  // namespace semap::app
