// The pipeline's output thread: turns what comes out of the map into per-frame figures and mesh deltas, and
// tells the sinks. A frame is told once the mesh change that contains it is published (the map extracts its
// surface every mesh_every_frames frames), so that its latency to the published mesh is known; drops and
// failures are told as soon as they are known. Not thread-safe: the output thread's alone.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "engine/pipeline/internal/item.h"
#include "engine/pipeline/timing_stats.h"

namespace semap::pipeline_internal {

class FrameReporter {
 public:
  // `sinks` are not owned; `summary` receives the sinks' errors and, from Finish(), the final figures.
  // `realtime`: frames have due times (FrameLatency::late_ms); `segment`: the pipeline has a segment stage.
  FrameReporter(const std::vector<PipelineSink*>& sinks, const PipelineClock& clock, Clock::time_point start,
                bool realtime, bool segment, PipelineSummary* summary);

  // Frames dropped or failed before the stages, and the drop counts by reason so far (DropReason's order).
  void SideEvents(const std::vector<SideEvent>& events,
                  const std::array<std::int64_t, kNumDropReasons>& dropped);
  // An item the map handed on, with the queues as they are now.
  void Frame(Item& item, const QueueSizes& queues);

 private:
  // An integrated frame whose mesh change has not been published yet.
  struct PendingFrame {
    FrameStats stats;
    double sensor_s = 0.0;
    std::optional<Pose3d> world_from_cam;
  };

  template <typename Call>
  void ForEachSink(Call&& call);
  void Integrated(Item& item, const QueueSizes& queues);
  void Final(const Item& item);
  void AddStageTimes(const Item& item, const QueueSizes& queues);
  void AddStep(const std::string& name, double ms);
  void TakeTotals(const MapUpdate* update);
  void PublishPending(const MeshDelta& delta);
  void AddLatencies(FrameStats* stats);

  const std::vector<PipelineSink*>& sinks_;
  const PipelineClock& clock_;
  Clock::time_point start_;
  bool realtime_;
  bool segment_;
  PipelineSummary* summary_;
  FrameStats stats_;
  std::array<TimingStats, kNumStages> timing_;
  TimingStats segment_timing_;                      // keyframes only
  std::map<std::string, TimingStats> step_timing_;  // "map.<step>"
  std::array<TimingStats, kNumLatencySteps> latency_timing_;
  // The map's surface snapshots become the deltas the sinks receive here, not on the map's thread.
  MeshPublisher publisher_;
  std::vector<PendingFrame> pending_;
};

}  // namespace semap::pipeline_internal
