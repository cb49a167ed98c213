// A live progress line for long runs (stderr), and warnings for skipped frames.
#pragma once

#include <chrono>
#include <cstdint>

#include "engine/pipeline/stages.h"

namespace semap::app {

// Prints at most every `interval_s`: on a terminal the line is rewritten in place, otherwise one line per
// interval (logs stay readable). Called from the pipeline's output thread.
class ProgressSink : public PipelineSink {
 public:
  ProgressSink(std::int64_t total_frames, double interval_s);
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override;
  void OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) override;
  void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) override;

 private:
  void Print(const FrameStats& stats, bool final);
  std::int64_t total_frames_;
  double interval_s_;
  bool tty_;
  std::chrono::steady_clock::time_point last_print_{};
};

}  // namespace semap::app
