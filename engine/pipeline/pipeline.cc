#include "engine/pipeline/pipeline.h"

#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "engine/core/check.h"
#include "engine/pipeline/bounded_queue.h"
#include "engine/pipeline/internal/admission_queue.h"
#include "engine/pipeline/internal/frame_pacer.h"
#include "engine/pipeline/internal/frame_reporter.h"
#include "engine/pipeline/internal/frame_tokens.h"
#include "engine/pipeline/internal/item.h"
#include "engine/pipeline/internal/label_budget.h"
#include "engine/pipeline/internal/pose_check.h"
#include "engine/pipeline/internal/threads.h"

namespace semap {

using pipeline_internal::AcceptedPose;
using pipeline_internal::AdmissionQueue;
using pipeline_internal::BoundedQueue;
using pipeline_internal::Clock;
using pipeline_internal::FramePacer;
using pipeline_internal::Item;
using pipeline_internal::kDepth;
using pipeline_internal::kMap;
using pipeline_internal::kNumDropReasons;
using pipeline_internal::kRead;
using pipeline_internal::kSegmentStageName;
using pipeline_internal::kSimplify;
using pipeline_internal::kStageNames;
using pipeline_internal::MsBetween;
using pipeline_internal::MsFromTo;
using pipeline_internal::PinCurrentThread;
using pipeline_internal::SegmentJob;
using pipeline_internal::SegmentResult;
using pipeline_internal::SetUpThread;
using pipeline_internal::SideEvent;

static_assert(PipelineOptions::kCpuSetSize == CPU_SETSIZE);

void PipelineOptions::Check() const {
  CheckDeclaredRanges(*this);
  cpu_set_t available;
  CPU_ZERO(&available);
  if (sched_getaffinity(0, sizeof(available), &available) != 0) return;
  for (int cpu : cpu_affinity) {
    // Pinning to a CPU this process may not run on would be silently ignored by the kernel.
    if (!CPU_ISSET(cpu, &available)) {
      throw OptionError(*this, cpu_affinity,
                        "no such CPU available to this process (it may use " +
                            pipeline_internal::AvailableCpus(available) + ")",
                        cpu);
    }
  }
}

int PipelineOptions::QueueCapacity() const {
  return mode == Mode::kRealtime ? realtime_frames_in_flight : queue_capacity;
}

int PipelineOptions::MeshEveryFrames() const {
  return mode == Mode::kRealtime ? realtime_mesh_every_frames : mesh_every_frames;
}

double CurrentRssMb() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0.0;
  long pages_total = 0, pages_resident = 0;
  const int n = std::fscanf(f, "%ld %ld", &pages_total, &pages_resident);
  std::fclose(f);
  if (n != 2) return 0.0;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double ProcessCpuSeconds() {
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0.0;
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

const char* DropReasonName(DropReason reason) {
  switch (reason) {
    case DropReason::kBehind:
      return "behind";
    case DropReason::kNoKeyframeLabels:
      return "no_keyframe_labels";
    case DropReason::kLost:
      return "lost";
  }
  return "unknown";
}

namespace {
// A reader that fails this many times in a row (e.g. the dataset vanished) ends the run.
constexpr int kMaxConsecutiveReadFailures = 100;
// Realtime: the input queue holds the newest frame, and the segment queue the newest keyframe (a keyframe
// that finds it full is not taken: the labels follow what ENet has time for).
constexpr int kRealtimeInputFrames = 1;
// Realtime label budget: keyframes at most this much sensor time apart (labels carried further than this
// by reprojection are stale; more: a slow machine labels less often and maps more frames).
constexpr double kMaxKeyframeGapS = 3.0;
// The label budget's stages, in LabelBudget::RecordStageMs's order.
constexpr int kBudgetDepth = 0, kBudgetSimplify = 1, kBudgetMap = 2;
constexpr int kRealtimeSegmentFrames = 1;
}  // namespace

struct Pipeline::Impl {
  // The reader's state between frames.
  struct ReadState {
    std::int64_t last_id = -1;
    int consecutive_failures = 0;
    std::optional<AcceptedPose> last_pose;
  };

  Pipeline& p;
  PipelineClock& clock;
  const bool realtime;
  BoundedQueue<SegmentJob> to_segment;
  AdmissionQueue<Item> to_depth;
  BoundedQueue<Item> to_simplify;
  BoundedQueue<Item> to_map;
  BoundedQueue<Item> to_output;
  pipeline_internal::FrameTokens tokens;  // realtime: frames between the input queue and the map's end
  std::atomic<bool> error_stop{false};
  std::mutex error_mutex;
  std::string fatal_error;
  std::atomic<std::int64_t> frames_read{0};
  std::mutex side_mutex;
  std::vector<SideEvent> side_events;                             // guarded by side_mutex
  std::array<std::int64_t, kNumDropReasons> dropped_by_reason{};  // guarded by side_mutex
  // Realtime with a segment stage and pipeline.realtime_label_budget: the keyframes' gap.
  std::optional<pipeline_internal::LabelBudget> label_budget;
  Clock::time_point start;
  double start_s = 0.0;            // `start` on the pipeline's clock
  ReadState state;                 // the reader thread's (first read before it starts)
  std::optional<Item> first_item;  // realtime: read before the clock started

  explicit Impl(Pipeline& pipeline)
      : p(pipeline),
        clock(*pipeline.clock_),
        realtime(pipeline.options_.mode == PipelineOptions::Mode::kRealtime),
        to_segment(realtime ? kRealtimeSegmentFrames : pipeline.options_.QueueCapacity()),
        to_depth(realtime ? kRealtimeInputFrames : pipeline.options_.QueueCapacity()),
        to_simplify(pipeline.options_.QueueCapacity()),
        to_map(pipeline.options_.QueueCapacity()),
        to_output(pipeline.options_.QueueCapacity()),
        tokens(realtime ? pipeline.options_.realtime_frames_in_flight : 0) {
    if (realtime && pipeline.segment_ && pipeline.options_.realtime_label_budget) {
      const PipelineOptions& o = pipeline.options_;
      const int max_gap = std::max(1, static_cast<int>(std::lround(kMaxKeyframeGapS * o.realtime_rate_hz)));
      label_budget.emplace(1000.0 / (o.realtime_rate_hz * o.realtime_speed), EngineCores(o.cpu_affinity),
                           std::min(pipeline.keyframe_every_frames_, max_gap), max_gap);
    }
  }

  // The CPUs the engine's threads may run on.
  static int EngineCores(const std::vector<int>& cpu_affinity) {
    if (!cpu_affinity.empty()) return static_cast<int>(cpu_affinity.size());
    return std::max(1u, std::thread::hardware_concurrency());
  }

  // Milliseconds on the pipeline's clock since `since_s` (a NowS()). The label budget measures on this clock,
  // the one the frames' periods are played on, not on the machine's: a clock that a test holds still
  // makes every stage cost nothing.
  double MsOnClockSince(double since_s) const { return MsFromTo(since_s, clock.NowS()); }

  // A stage's time on a frame, for the label budget.
  void Budget(int stage, double ms) {
    if (label_budget) label_budget->RecordStageMs(stage, ms);
  }

  bool Stopping() const { return p.stop_requested_.load() || error_stop.load(); }

  // Records a stage failure on `item`; with on_error = stop the run ends after the frames in flight.
  void Fail(Item& item, const char* stage, const std::string& what) {
    item.error_stage = stage;
    item.error = what.empty() ? "unknown error" : what;
    if (p.options_.on_error == PipelineOptions::OnError::kStop) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (fatal_error.empty())
        fatal_error =
            std::string(stage) + " failed on frame " + std::to_string(item.frame_id) + ": " + item.error;
      error_stop.store(true);
    }
  }

  // A frame that could not be read or whose pose is unusable; too many in a row (the dataset vanished, the
  // poses jumped for good) end the run.
  void FailRead(Item& item, const char* stage, const std::string& what, int* consecutive_failures) {
    Fail(item, stage, what);
    if (++*consecutive_failures >= kMaxConsecutiveReadFailures) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (fatal_error.empty()) {
        fatal_error = std::to_string(*consecutive_failures) +
                      " frames in a row could not be read or had an "
                      "unusable pose; last: " +
                      what;
      }
      error_stop.store(true);
    }
  }

  // A frame that leaves the pipeline before the stages: dropped for `reason`, or, when it had failed to be
  // read already, failed as it was.
  void LeaveEarly(const Item& item, DropReason reason) {
    SideEvent e{item.frame_id, item.timestamp_s, std::nullopt, item.error_stage, item.error};
    std::lock_guard<std::mutex> lock(side_mutex);
    if (!item.failed()) {
      e.dropped = reason;
      ++dropped_by_reason[static_cast<int>(reason)];
    }
    side_events.push_back(std::move(e));
  }

  // Counts the frames the reader says it lost since it was last asked.
  void CountLost() {
    const std::vector<FrameReader::LostFrame> lost = p.reader_->TakeLost();
    if (lost.empty()) return;
    std::lock_guard<std::mutex> lock(side_mutex);
    for (const FrameReader::LostFrame& l : lost) {
      side_events.push_back(SideEvent{l.frame_id, l.timestamp_s, DropReason::kLost, {}, {}});
      ++dropped_by_reason[static_cast<int>(DropReason::kLost)];
    }
  }

  // The frame's sensor time on the pipeline's clock, and its sensing time on the Unix clock: a frame sensed
  // on another host (Frame::sensed_unix_s set) is as old here as it is there (the hosts' clocks agree to
  // within what NTP or PTP give); any other frame was sensed at `*sensor_s` (its due time in realtime mode,
  // its read otherwise).
  void SetSensed(Frame* frame, double* sensor_s) {
    const double now_s = clock.NowS();
    const double unix_now_s = UnixNowS();
    if (frame->sensed_unix_s > 0.0) {
      *sensor_s = now_s - std::max(0.0, unix_now_s - frame->sensed_unix_s);
    } else {
      frame->sensed_unix_s = unix_now_s - (now_s - *sensor_s);
    }
  }

  static double UnixNowS() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  }

  // Reads the next frame into `item` (a failed read or an unusable pose is recorded on it); false at the end
  // of the sequence.
  bool ReadOne(Item* item, ReadState* state) {
    try {
      std::optional<Frame> frame = p.reader_->Next();
      if (!frame) return false;
      item->frame_id = frame->id;
      item->timestamp_s = frame->timestamp_s;
      item->world_from_cam = frame->world_from_cam;
      state->last_id = item->frame_id;
      const std::string pose_problem =
          frame->world_from_cam
              ? pipeline_internal::PoseProblem(*frame->world_from_cam, frame->timestamp_s, state->last_pose,
                                               p.options_.max_speed_mps, 1.0 / p.options_.realtime_rate_hz)
              : std::string();
      if (pose_problem.empty()) {
        state->consecutive_failures = 0;
        if (frame->world_from_cam) {
          state->last_pose =
              AcceptedPose{frame->id, frame->timestamp_s, frame->world_from_cam->translation()};
        }
        item->frame = std::make_unique<Frame>(std::move(*frame));
      } else {
        item->world_from_cam.reset();
        FailRead(*item, "pose", "frame " + std::to_string(item->frame_id) + ": " + pose_problem,
                 &state->consecutive_failures);
      }
    } catch (const std::exception& e) {
      item->frame_id = state->last_id + 1;
      state->last_id = item->frame_id;
      FailRead(*item, kStageNames[kRead], e.what(), &state->consecutive_failures);
    }
    return true;
  }

  // ReadOne, timed and counted.
  bool ReadTimed(Item* item, ReadState* state) {
    const auto t0 = Clock::now();
    if (!ReadOne(item, state)) return false;
    item->ms[kRead] = MsBetween(t0, Clock::now());
    ++frames_read;
    return true;
  }

  // Realtime: reads the first frame before the clock starts and lets the stages prepare on it (ENet's first
  // forward pass allocates its layers), as a camera driver starts once its node is ready.
  void ReadFirstAndPrepare(const std::vector<std::unique_ptr<DepthStage>>& depth_stages) {
    Item item;
    if (!ReadTimed(&item, &state)) return;
    if (item.frame) {
      try {
        if (p.segment_) p.segment_->Prepare(*item.frame);
        for (const auto& stage : depth_stages) stage->Prepare(*item.frame);
      } catch (const std::exception&) {
        // Not the frame's processing: the stage that cannot prepare fails on the frame itself, counted there.
      }
    }
    first_item = std::move(item);
  }

  // Realtime: waits until `item` is due (its pixels exist from then on, as a camera delivers them); a frame
  // that could not be read is passed on at once, to be counted. False when the run is asked to stop
  // meanwhile: the frame was never delivered, and is not counted as read.
  bool WaitUntilDue(Item* item, FramePacer* pacer) {
    item->times.due_s = pacer->NextDueS(item->timestamp_s);
    if (item->failed()) return true;
    clock.SleepUntilS(item->times.due_s, [this] { return Stopping(); });
    if (!Stopping()) return true;
    --frames_read;
    return false;
  }

  void ReadLoop() {
    // In realtime mode the reader is the sensor's clock: it keeps the map's priority.
    SetUpThread("semap-read", p.options_.cpu_affinity, realtime ? 0 : p.options_.feeder_nice);
    FramePacer pacer(start_s, p.options_.realtime_rate_hz, p.options_.realtime_speed);
    KeyframeSchedule schedule(p.keyframe_every_frames_);
    Keyframes keyframes;
    while (!Stopping()) {
      Item item;
      if (first_item) {
        item = std::move(*first_item);
        first_item.reset();
      } else if (!ReadTimed(&item, &state)) {
        break;
      }
      CountLost();
      if (realtime && !WaitUntilDue(&item, &pacer)) break;
      item.times.sensor_s = realtime ? item.times.due_s : clock.NowS();
      if (item.frame) SetSensed(item.frame.get(), &item.times.sensor_s);
      if (p.segment_ && item.frame && !AttachKeyframe(item, &schedule, &keyframes)) {
        LeaveEarly(item, DropReason::kNoKeyframeLabels);  // realtime: the segment queue was full
        continue;
      }
      item.times.entered_s = clock.NowS();
      if (!realtime) {
        to_depth.PushWaiting(std::move(item));
      } else if (std::optional<Item> evicted = to_depth.PushEvictingOldest(std::move(item))) {
        LeaveEarly(*evicted, DropReason::kBehind);  // counted, never silent
      }
    }
    CountLost();
    if (p.segment_) to_segment.PushEnd();
    for (int w = 0; w < p.options_.depth_workers; ++w) to_depth.PushEnd();
  }

  // The keyframes whose labels the reader has handed out, newest last: the current one, and in realtime mode
  // the newest whose labels were ready (the reader thread's).
  struct Keyframes {
    std::shared_future<SegmentResult> current;
    std::deque<std::shared_future<SegmentResult>> pending;  // realtime: queued after `ready`, oldest first
    std::shared_future<SegmentResult> ready;
  };

  static bool IsReady(const std::shared_future<SegmentResult>& f) {
    return f.valid() && f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  }

  // Gives `item` (a frame read with a usable pose, or none) the labels of its keyframe: the frame itself when
  // it is due (its left image is queued to the segment thread), else the current keyframe; in realtime mode
  // also the newest keyframe whose labels are ready, for the depth worker to take when the current one's are
  // not (ENet takes longer than a frame period: waiting would add it to every frame's latency). Returns false
  // when there is none: realtime mode, the segment queue full and no keyframe taken yet.
  bool AttachKeyframe(Item& item, KeyframeSchedule* schedule, Keyframes* keyframes) {
    const Frame& f = *item.frame;
    const bool has_pose = f.world_from_cam.has_value();
    if (label_budget) schedule->SetEveryFrames(label_budget->GapFrames());
    if (schedule->IsDue(f.id, has_pose)) {
      SegmentJob job;
      job.keyframe.id = f.id;
      job.keyframe.timestamp_s = f.timestamp_s;
      job.keyframe.left = f.left;  // shares the pixels (read-only on both threads)
      job.keyframe.calibration = f.calibration;
      job.keyframe.world_from_cam = f.world_from_cam;
      std::shared_future<SegmentResult> labels = job.labels.get_future().share();
      bool queued = true;
      if (realtime) {
        queued = to_segment.TryPush(std::move(job));
      } else {
        to_segment.Push(std::move(job));
      }
      if (queued) {
        schedule->Record(f.id, has_pose);
        keyframes->current = labels;
        if (realtime) keyframes->pending.push_back(std::move(labels));
        item.keyframe = true;
      }
    }
    while (!keyframes->pending.empty() && IsReady(keyframes->pending.front())) {
      keyframes->ready = std::move(keyframes->pending.front());
      keyframes->pending.pop_front();
    }
    if (!keyframes->current.valid()) return false;
    item.keyframe_labels = keyframes->current;
    item.ready_labels = keyframes->ready;
    return true;
  }

  // Segments the queued keyframes in order; every job's promise is kept (a value or the error), so no depth
  // worker waits for ever. Stops at the end marker, after every queued keyframe (frames in flight need them).
  void SegmentLoop() {
    SetUpThread("semap-segment", p.options_.cpu_affinity, p.options_.feeder_nice);
    while (auto job = to_segment.Pop()) {
      const auto t0 = Clock::now();
      const double t0_s = clock.NowS();
      try {
        auto labels = std::make_shared<KeyframeLabels>();
        labels->frame_id = job->keyframe.id;
        labels->world_from_cam = job->keyframe.world_from_cam;
        labels->labels = p.segment_->Process(job->keyframe);
        const double ms = MsBetween(t0, Clock::now());
        if (label_budget) label_budget->RecordSegmentMs(MsOnClockSince(t0_s));
        job->labels.set_value({std::move(labels), ms});
      } catch (const std::exception& e) {
        job->labels.set_exception(std::make_exception_ptr(
            std::runtime_error("keyframe " + std::to_string(job->keyframe.id) + ": " + e.what())));
      }
    }
  }

  // The labels `item` takes: its keyframe's, waited for; in realtime mode, when those are not ready, the
  // newest keyframe's that were ready when it was read. Rethrows the segmenter's error.
  const SegmentResult& LabelsOf(const Item& item) const {
    if (realtime && item.ready_labels.valid() && !IsReady(item.keyframe_labels))
      return item.ready_labels.get();
    return item.keyframe_labels.get();  // waits for the segment thread
  }

  // The depth stage on one frame, after its keyframe's labels when it has a keyframe.
  void ComputeDepth(Item* item, DepthStage* stage) {
    const auto t0 = Clock::now();
    double depth_start_s = clock.NowS();  // after the wait for labels, on the pipeline's clock
    const SegmentResult* keyframe = nullptr;
    if (item->keyframe_labels.valid()) {
      try {
        keyframe = &LabelsOf(*item);
        // The segmenter's time on this keyframe, when these are its own labels.
        if (item->keyframe && keyframe->labels && keyframe->labels->frame_id == item->frame_id) {
          item->segment_ms = keyframe->ms;
        }
      } catch (const std::exception& e) {
        Fail(*item, kSegmentStageName, e.what());
      }
      item->label_wait_ms = MsBetween(t0, Clock::now());
      item->times.labels_s = clock.NowS();
      depth_start_s = item->times.labels_s;
    }
    if (!item->failed()) {
      try {
        item->cloud = stage->Process(*item->frame, keyframe != nullptr ? keyframe->labels.get() : nullptr);
      } catch (const std::exception& e) {
        Fail(*item, kStageNames[kDepth], e.what());
      }
    }
    item->ms[kDepth] = MsBetween(t0, Clock::now());
    item->times.depth_s = clock.NowS();
    if (!item->failed()) Budget(kBudgetDepth, MsFromTo(depth_start_s, item->times.depth_s));
    if (!item->keyframe_labels.valid())
      item->times.labels_s = item->times.depth_s;  // labelled with the depth
  }

  void DepthLoop(DepthStage* stage) {
    SetUpThread("semap-depth", p.options_.cpu_affinity, p.options_.feeder_nice);
    while (true) {
      tokens.Acquire();
      auto popped = to_depth.Pop();
      if (!popped) {
        tokens.Release();
        break;
      }
      Item& item = popped->item;
      item.seq = popped->order;
      if (!item.failed()) ComputeDepth(&item, stage);
      item.frame.reset();         // images are not needed any more
      item.keyframe_labels = {};  // nor the keyframes' labels
      item.ready_labels = {};
      to_simplify.Push(std::move(item));
    }
    to_simplify.PushEnd();
  }

  // Restores frame order after the parallel depth workers, then simplifies.
  void SimplifyLoop() {
    SetUpThread("semap-simplify", p.options_.cpu_affinity, p.options_.feeder_nice);
    std::map<std::int64_t, Item> pending;
    std::int64_t next_seq = 0;
    int ends = 0;
    while (ends < p.options_.depth_workers) {
      auto item = to_simplify.Pop();
      if (!item) {
        ++ends;
        continue;
      }
      pending.emplace(item->seq, std::move(*item));
      for (auto it = pending.find(next_seq); it != pending.end(); it = pending.find(++next_seq)) {
        Item ready = std::move(it->second);
        pending.erase(it);
        if (!ready.failed()) {
          const auto t0 = Clock::now();
          const double t0_s = clock.NowS();
          ready.points_in = static_cast<std::int64_t>(ready.cloud.size());
          try {
            ready.cloud = p.simplify_->Process(std::move(ready.cloud), &ready.counts);
          } catch (const std::exception& e) {
            Fail(ready, kStageNames[kSimplify], e.what());
          }
          ready.ms[kSimplify] = MsBetween(t0, Clock::now());
          Budget(kBudgetSimplify, MsOnClockSince(t0_s));
        }
        to_map.Push(std::move(ready));
      }
    }
    SEMAP_ASSERT(pending.empty(), pending.size() << " frames lost in reordering");
    to_map.PushEnd();
  }

  void MapLoop() {
    SetUpThread("semap-map", p.options_.cpu_affinity);
    while (auto item = to_map.Pop()) {
      if (!item->failed()) {
        const auto t0 = Clock::now();
        const double t0_s = clock.NowS();
        try {
          if (!item->world_from_cam) throw std::runtime_error("frame has no pose");
          item->update = p.map_->Process(item->cloud, *item->world_from_cam);
        } catch (const std::exception& e) {
          Fail(*item, kStageNames[kMap], e.what());
        }
        item->ms[kMap] = MsBetween(t0, Clock::now());
        item->times.map_s = clock.NowS();
        Budget(kBudgetMap, MsFromTo(t0_s, item->times.map_s));
      }
      item->cloud = LabelledCloud{};
      tokens.Release();  // integrated (or failed): the next frame may go
      to_output.Push(std::move(*item));
    }
    Item last;
    last.final = true;
    const auto t0 = Clock::now();
    try {
      last.update = p.map_->Finish();
    } catch (const std::exception& e) {
      Fail(last, kStageNames[kMap], e.what());
    }
    last.ms[kMap] = MsBetween(t0, Clock::now());
    to_output.Push(std::move(last));
    to_output.PushEnd();
  }

  // The output thread: per-frame figures, mesh deltas and the sinks' calls (FrameReporter).
  void OutputLoop(PipelineSummary* summary) {
    pipeline_internal::FrameReporter reporter(p.sinks_, clock, start, realtime, p.segment_ != nullptr,
                                              summary);
    while (auto item = to_output.Pop()) {
      std::vector<SideEvent> events;
      std::array<std::int64_t, kNumDropReasons> dropped{};
      {
        std::lock_guard<std::mutex> lock(side_mutex);
        events.swap(side_events);
        dropped = dropped_by_reason;
      }
      reporter.SideEvents(events, dropped);
      reporter.Frame(*item, {to_segment.size(), to_depth.size(), to_simplify.size(), to_map.size()});
    }
  }
};

Pipeline::Pipeline(const PipelineOptions& options, std::unique_ptr<FrameReader> reader,
                   DepthStageFactory depth_factory, std::unique_ptr<SimplifyStage> simplify,
                   std::unique_ptr<MapStage> map)
    : options_(options),
      reader_(std::move(reader)),
      depth_factory_(std::move(depth_factory)),
      simplify_(std::move(simplify)),
      map_(std::move(map)) {
  options_.Check();
  SEMAP_ASSERT(reader_ && depth_factory_ && simplify_ && map_);
}

Pipeline::~Pipeline() = default;

void Pipeline::SetSegmentStage(std::unique_ptr<SegmentStage> segment, int keyframe_every_frames) {
  SEMAP_ASSERT(segment != nullptr);
  SEMAP_ASSERT(keyframe_every_frames >= 1, "keyframe interval " << keyframe_every_frames);
  segment_ = std::move(segment);
  keyframe_every_frames_ = keyframe_every_frames;
}

PipelineSummary Pipeline::Run() {
  Impl impl(*this);
  PipelineSummary summary;
  std::vector<std::unique_ptr<DepthStage>> depth_stages;
  for (int w = 0; w < options_.depth_workers; ++w) depth_stages.push_back(depth_factory_());
  PinCurrentThread(options_.cpu_affinity);
  const pipeline_internal::OpenCvThreads opencv_threads(options_.opencv_threads);
  if (options_.feeder_nice > 0) pipeline_internal::StartTbbWorkers();
  if (impl.realtime) impl.ReadFirstAndPrepare(depth_stages);
  // Everything is set up: the first frame is due now.
  impl.start = Clock::now();
  impl.start_s = clock_->NowS();
  std::vector<std::thread> threads;
  threads.emplace_back([&] { impl.ReadLoop(); });
  if (segment_) threads.emplace_back([&] { impl.SegmentLoop(); });
  for (auto& stage : depth_stages) threads.emplace_back([&impl, s = stage.get()] { impl.DepthLoop(s); });
  threads.emplace_back([&] { impl.SimplifyLoop(); });
  threads.emplace_back([&] { impl.MapLoop(); });
  impl.OutputLoop(&summary);
  for (auto& t : threads) t.join();
  summary.frames_read = impl.frames_read.load();
  summary.stopped_early = stop_requested_.load() || impl.error_stop.load();
  summary.fatal_error = impl.fatal_error;
  return summary;
}

}  // namespace semap
