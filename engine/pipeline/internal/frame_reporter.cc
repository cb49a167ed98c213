#include "engine/pipeline/internal/frame_reporter.h"

namespace semap::pipeline_internal {

namespace {

StageTiming Timing(const std::string& name, const TimingStats& t, int occupancy) {
  return {name, t.last(), t.mean(), t.Percentile(0.5), t.Percentile(0.95), t.max(), occupancy};
}

}  // namespace

FrameReporter::FrameReporter(const std::vector<PipelineSink*>& sinks, const PipelineClock& clock,
                             Clock::time_point start, bool realtime, bool segment, PipelineSummary* summary)
    : sinks_(sinks),
      clock_(clock),
      start_(start),
      realtime_(realtime),
      segment_(segment),
      summary_(summary) {}

// A sink that throws (e.g. its output folder became unwritable) does not stop the run: the error is recorded
// in the summary and the sink is called again for the next frames.
template <typename Call>
void FrameReporter::ForEachSink(Call&& call) {
  for (auto* s : sinks_) {
    try {
      call(*s);
    } catch (const std::exception& e) {
      ++summary_->sink_errors;
      if (summary_->first_sink_error.empty()) summary_->first_sink_error = e.what();
    }
  }
}

void FrameReporter::SideEvents(const std::vector<SideEvent>& events,
                               const std::array<std::int64_t, kNumDropReasons>& dropped) {
  stats_.dropped_by_reason.clear();
  stats_.frames_dropped = 0;
  for (int r = 0; r < kNumDropReasons; ++r) {
    stats_.dropped_by_reason.emplace_back(DropReasonName(static_cast<DropReason>(r)), dropped[r]);
    stats_.frames_dropped += dropped[r];
  }
  for (const SideEvent& e : events) {
    if (e.dropped) {
      ForEachSink(
          [&](PipelineSink& s) { s.OnFrameDropped(e.frame_id, e.timestamp_s, DropReasonName(*e.dropped)); });
    } else {
      ++stats_.frames_failed;
      ForEachSink([&](PipelineSink& s) { s.OnFrameError(e.frame_id, e.stage, e.what); });
    }
  }
}

void FrameReporter::Frame(Item& item, const QueueSizes& queues) {
  stats_.elapsed_s = MsBetween(start_, Clock::now()) / 1000.0;
  if (item.final) {
    Final(item);
    summary_->final_stats = stats_;
  } else if (item.failed()) {
    ++stats_.frames_failed;
    ForEachSink([&](PipelineSink& s) { s.OnFrameError(item.frame_id, item.error_stage, item.error); });
  } else {
    Integrated(item, queues);
  }
}

void FrameReporter::AddStageTimes(const Item& item, const QueueSizes& queues) {
  const std::array<int, kNumStages> occupancy = {0, queues.depth, queues.simplify, queues.map};
  stats_.stages.clear();
  for (int s = 0; s < kNumStages; ++s) {
    timing_[s].Add(item.ms[s]);
    stats_.stages.push_back(Timing(kStageNames[s], timing_[s], occupancy[s]));
    if (s == kRead && segment_) {
      // The segmenter's time on this frame (0 unless it is a keyframe); the statistics are over keyframes.
      if (item.keyframe) segment_timing_.Add(item.segment_ms);
      StageTiming t = Timing(kSegmentStageName, segment_timing_, queues.segment);
      t.last_ms = item.segment_ms;
      stats_.stages.push_back(t);
    }
  }
  if (segment_) AddStep(kLabelWaitStepName, item.label_wait_ms);
  for (const StepTime& step : item.update.steps)
    AddStep(std::string(kStageNames[kMap]) + "." + step.name, step.ms);
}

void FrameReporter::AddStep(const std::string& name, double ms) {
  TimingStats& t = step_timing_[name];
  t.Add(ms);
  stats_.stages.push_back(Timing(name, t, 0));
}

// The run's totals as of now: frame rate, the map's sizes (from `update`; kept as they were without one), the
// process's memory and CPU.
void FrameReporter::TakeTotals(const MapUpdate* update) {
  stats_.fps = stats_.elapsed_s > 0 ? static_cast<double>(stats_.frames_processed) / stats_.elapsed_s : 0.0;
  if (update != nullptr) {
    stats_.map_vertices = update->vertices;
    stats_.map_cells = update->cells;
    stats_.map_rays = update->rays;
  }
  stats_.rss_mb = CurrentRssMb();
  stats_.cpu_s = ProcessCpuSeconds();
}

void FrameReporter::Integrated(Item& item, const QueueSizes& queues) {
  ++stats_.frames_processed;
  stats_.frame_id = item.frame_id;
  stats_.timestamp_s = item.timestamp_s;
  AddStageTimes(item, queues);
  stats_.points_in = item.points_in;
  stats_.points_kept = 0;
  for (const auto& c : item.counts) stats_.points_kept += c.kept;
  if (item.counts.empty()) stats_.points_kept = stats_.points_in;
  stats_.class_counts = item.counts;
  const ClockTimes& t = item.times;
  stats_.latency = FrameLatency{};
  stats_.latency.late_ms = realtime_ ? MsFromTo(t.due_s, t.entered_s) : 0.0;
  stats_.latency.depth_ms = MsFromTo(t.sensor_s, t.depth_s);
  stats_.latency.labels_ms = MsFromTo(t.sensor_s, t.labels_s);
  stats_.latency.map_ms = MsFromTo(t.sensor_s, t.map_s);
  TakeTotals(&item.update);
  MeshDelta delta;
  if (item.update.mesh) {
    delta = publisher_.Publish(item.update);
    stats_.mesh_triangles = publisher_.published_triangles();
  }
  pending_.push_back({stats_, t.sensor_s, item.world_from_cam});
  if (item.update.mesh) PublishPending(delta);  // else published with a later frame's mesh change
}

// Tells the sinks the frames waiting for `delta`, which contains their changes: all but the last with an
// empty delta of their own, the last with `delta`.
void FrameReporter::PublishPending(const MeshDelta& delta) {
  const double published_s = clock_.NowS();
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    PendingFrame& f = pending_[i];
    f.stats.latency.published_ms = MsFromTo(f.sensor_s, published_s);
    AddLatencies(&f.stats);
    MeshDelta none;
    none.frame_id = f.stats.frame_id;
    const MeshDelta& d = i + 1 == pending_.size() ? delta : none;
    ForEachSink([&](PipelineSink& s) { s.OnFrame(f.stats, d, f.world_from_cam); });
  }
  stats_.latency = pending_.back().stats.latency;  // the run's figures as of the newest frame published
  pending_.clear();
}

void FrameReporter::AddLatencies(FrameStats* stats) {
  const FrameLatency& l = stats->latency;
  const std::array<double, kNumLatencySteps> ms = {l.depth_ms, l.labels_ms, l.map_ms, l.published_ms};
  stats->latencies.clear();
  for (int i = 0; i < kNumLatencySteps; ++i) {
    latency_timing_[i].Add(ms[i]);
    stats->latencies.push_back(Timing(kLatencyStepNames[i], latency_timing_[i], 0));
  }
  stats_.latencies = stats->latencies;
}

void FrameReporter::Final(const Item& item) {
  if (item.failed()) {
    ForEachSink([&](PipelineSink& s) { s.OnFrameError(-1, item.error_stage, item.error); });
  }
  // A failed finish carries no update: the map as of the last frame is what was published. The frames still
  // waiting for a mesh change are told before the final one, which contains theirs.
  if (!pending_.empty()) {
    MeshDelta none;
    none.frame_id = pending_.back().stats.frame_id;
    PublishPending(none);
  }
  const MeshDelta delta = publisher_.Publish(item.update);
  stats_.mesh_triangles = publisher_.published_triangles();
  TakeTotals(item.failed() ? nullptr : &item.update);
  ForEachSink([&](PipelineSink& s) { s.OnFinish(stats_, delta); });
}

}  // namespace semap::pipeline_internal
