// Realtime mode: how many frames apart the keyframes that the segmenter (ENet) labels are, from the time
// left in the frame budget. The engine's cores give cores × frame period of CPU per frame; what a frame's
// depth, simplification and map take of it is measured as the run goes (on the pipeline's clock), and the
// segmenter gets the rest: a keyframe every ⌈segment ms / (cores × period − frame ms)⌉ frames, within
// [1, max_gap_frames]. A machine with time to spare labels every frame or two; one that is behind labels
// seldom and gives the depth and the map the CPU. Thread-safe: the stages record from their threads, the
// reader asks.
#pragma once

#include <mutex>

namespace semap::pipeline_internal {

class LabelBudget {
 public:
  // Weight of the newest measurement in the running means (higher: follows changes faster, noisier).
  static constexpr double kSmoothing = 0.2;

  // frame_period_ms > 0 (the sensor's period divided by the playing speed), cores ≥ 1,
  // 1 ≤ first_gap_frames ≤ max_gap_frames: the gap until both costs are measured.
  LabelBudget(double frame_period_ms, int cores, int first_gap_frames, int max_gap_frames);

  // One frame's time in a stage other than the segmenter (depth without the wait for labels, simplify, map).
  void RecordStageMs(int stage, double ms);
  // The segmenter's time on one keyframe.
  void RecordSegmentMs(double ms);

  // Frames between keyframes now.
  int GapFrames() const;

  // The gap for the given mean costs (the rule above), for tests and reports.
  static int GapFor(double frame_period_ms, int cores, double frame_ms, double segment_ms,
                    int max_gap_frames);

 private:
  static constexpr int kStages = 3;  // depth, simplify, map: the frame's cost is their sum

  const double frame_period_ms_;
  const int cores_;
  const int first_gap_frames_;
  const int max_gap_frames_;
  mutable std::mutex mutex_;
  double stage_ms_[kStages] = {0.0, 0.0, 0.0};  // guarded by mutex_; running means
  bool stage_seen_[kStages] = {false, false, false};
  double segment_ms_ = 0.0;
  bool segment_seen_ = false;
};

}  // namespace semap::pipeline_internal
