#include "engine/pipeline/pipeline.h"

#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <map>
#include <mutex>
#include <thread>

#include <opencv2/core/utility.hpp>

#include "engine/core/check.h"
#include "engine/core/parallel.h"
#include "engine/pipeline/bounded_queue.h"
#include "engine/pipeline/timing_stats.h"

namespace semap {

namespace {

// "0-3, 6" for the CPUs in `set`.
std::string AvailableCpus(const cpu_set_t& set) {
  std::string out;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    int last = c;
    while (last + 1 < CPU_SETSIZE && CPU_ISSET(last + 1, &set)) ++last;
    out += (out.empty() ? "" : ", ") + std::to_string(c) + (last > c ? "-" + std::to_string(last) : "");
    c = last;
  }
  return out;
}

}  // namespace

void PipelineOptions::Check() const {
  SEMAP_CHECK_OPTION(realtime_rate_hz > 0.0, "realtime_rate_hz", realtime_rate_hz, "must be > 0");
  SEMAP_CHECK_OPTION(depth_workers >= 1 && depth_workers <= 64, "depth_workers", depth_workers, "must be in [1, 64]");
  SEMAP_CHECK_OPTION(queue_capacity >= 1, "queue_capacity", queue_capacity, "must be >= 1");
  SEMAP_CHECK_OPTION(mesh_every_frames >= 1, "mesh_every_frames", mesh_every_frames, "must be >= 1");
  SEMAP_CHECK_OPTION(feeder_nice >= 0 && feeder_nice <= 19, "feeder_nice", feeder_nice, "must be in [0, 19]");
  SEMAP_CHECK_OPTION(opencv_threads >= 0, "opencv_threads", opencv_threads, "must be >= 0 (0 = OpenCV's setting)");
  SEMAP_CHECK_OPTION(max_speed_mps >= 0.0 && std::isfinite(max_speed_mps), "max_speed_mps", max_speed_mps,
                     "must be >= 0 (0 = no check)");
  cpu_set_t available;
  CPU_ZERO(&available);
  const bool known = sched_getaffinity(0, sizeof(available), &available) == 0;
  for (int cpu : cpu_affinity) {
    SEMAP_CHECK_OPTION(cpu >= 0 && cpu < CPU_SETSIZE, "cpu_affinity", cpu, "CPU ids must be in [0, CPU_SETSIZE)");
    // Pinning to a CPU this process may not run on would be silently ignored by the kernel.
    SEMAP_CHECK_OPTION(!known || CPU_ISSET(cpu, &available), "cpu_affinity", cpu,
                       "no such CPU available to this process (it may use " + AvailableCpus(available) + ")");
  }
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

namespace {

using Clock = std::chrono::steady_clock;

enum StageIndex { kRead, kDepth, kSimplify, kMap, kNumStages };
constexpr std::array<const char*, kNumStages> kStageNames = {"read", "depth", "simplify", "map"};
// A reader that fails this many times in a row (e.g. the dataset vanished) ends the run.
constexpr int kMaxConsecutiveReadFailures = 100;

double MsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// A keyframe's labels as the segment thread hands them over, with the segmenter's time.
struct SegmentResult {
  std::shared_ptr<const KeyframeLabels> labels;
  double ms = 0.0;
};

// A keyframe queued to the segment thread: its left image and pose (shared with the frame's item, never
// modified), and the promise its frames wait on.
struct SegmentJob {
  Frame keyframe;
  std::promise<SegmentResult> labels;
};

// "segment": the keyframes' segmentation; "depth.label_wait": a depth worker waiting for it.
constexpr const char* kSegmentStageName = "segment";
constexpr const char* kLabelWaitStepName = "depth.label_wait";

// One frame travelling through the stages.
struct Item {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  std::int64_t seq = 0;  // position in the stream of frames that entered the pipeline
  std::unique_ptr<Frame> frame;  // until the depth stage
  // With a segment stage: the labels of this frame's keyframe (until the depth stage), whether the frame is
  // a keyframe itself, the segmenter's time on it and the depth worker's wait for the labels.
  std::shared_future<SegmentResult> keyframe_labels;
  bool keyframe = false;
  double segment_ms = 0.0;
  double label_wait_ms = 0.0;
  std::optional<Pose3d> world_from_cam;
  LabelledCloud cloud;
  std::vector<ClassPointCount> counts;
  std::int64_t points_in = 0;
  MapUpdate update;
  bool final = false;  // the map's Finish() output
  std::string error_stage;
  std::string error;
  std::array<double, kNumStages> ms{};
  bool failed() const { return !error.empty(); }
};

// Why a frame's pose cannot go into the map, or "" when it can: non-finite entries, a linear part that is
// not a rotation, or (against the last accepted frame `last`) a speed above options.max_speed_mps.
struct AcceptedPose {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  Eigen::Vector3d position;
};
std::string PoseProblem(const Pose3d& pose, double timestamp_s, const std::optional<AcceptedPose>& last,
                        const PipelineOptions& options) {
  if (!pose.matrix().allFinite()) return "pose is not finite (NaN or inf)";
  const Eigen::Matrix3d r = pose.linear();
  const double orthogonality_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality_error > 1e-3 || r.determinant() <= 0.0) {
    return "pose rotation is not a rotation (|RᵀR - I| = " + std::to_string(orthogonality_error) +
           ", det " + std::to_string(r.determinant()) + ")";
  }
  if (!last || options.max_speed_mps <= 0.0) return "";
  const double dt_s = std::max(timestamp_s - last->timestamp_s, 1.0 / options.realtime_rate_hz);
  const double moved_m = (pose.translation() - last->position).norm();
  if (moved_m <= options.max_speed_mps * dt_s) return "";
  char text[256];
  std::snprintf(text, sizeof(text),
                "pose jumps %.1f m in %.2f s since frame %lld (%.0f m/s > max_speed_mps %.0f)", moved_m, dt_s,
                static_cast<long long>(last->frame_id), moved_m / dt_s, options.max_speed_mps);
  return text;
}

void PinCurrentThread(const std::vector<int>& cpus) {
  if (cpus.empty()) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);  // best effort: unknown CPUs are ignored
}

// Names the calling pipeline thread (as `top -H` and gdb show it; at most 15 characters), pins it, and makes
// it `nicer` steps nicer than it is (best effort: a nice value is per thread on Linux).
void SetUpThread(const char* name, const std::vector<int>& cpus, int nicer = 0) {
  pthread_setname_np(pthread_self(), name);
  PinCurrentThread(cpus);
  if (nicer > 0) {
    const auto tid = static_cast<id_t>(syscall(SYS_gettid));
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, tid);
    if (errno == 0) setpriority(PRIO_PROCESS, tid, nice + nicer);
  }
}

// Starts TBB's worker threads from the calling thread. A thread takes its nice value (and CPU affinity) from
// the thread that starts it, and TBB starts its workers on first demand: started by a niced feeder (OpenCV's
// SGBM runs on TBB), they would run the map's parallel votes at the feeders' priority. Best effort: a worker
// that does not start within the wait starts later, from whichever thread needs it.
void StartTbbWorkers() {
  constexpr auto kMaxWait = std::chrono::milliseconds(200);
  OnEveryThread(kMaxWait, [] {});
}

// OpenCV's thread count (process-wide) for a scope, restored when it ends; 0 leaves it as it is.
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int threads) : previous_(cv::getNumThreads()), set_(threads > 0) {
    if (set_) cv::setNumThreads(threads);
  }
  ~OpenCvThreads() {
    if (set_) cv::setNumThreads(previous_);
  }
  OpenCvThreads(const OpenCvThreads&) = delete;
  OpenCvThreads& operator=(const OpenCvThreads&) = delete;

 private:
  int previous_;
  bool set_;
};

}  // namespace

struct Pipeline::Impl {
  Pipeline& p;
  pipeline_internal::BoundedQueue<SegmentJob> to_segment;
  pipeline_internal::BoundedQueue<Item> to_depth;
  pipeline_internal::BoundedQueue<Item> to_simplify;
  pipeline_internal::BoundedQueue<Item> to_map;
  pipeline_internal::BoundedQueue<Item> to_output;
  std::atomic<bool> error_stop{false};
  std::mutex error_mutex;
  std::string fatal_error;
  std::atomic<std::int64_t> frames_read{0};
  std::atomic<std::int64_t> frames_dropped{0};
  Clock::time_point start;

  explicit Impl(Pipeline& pipeline)
      : p(pipeline),
        to_segment(pipeline.options_.queue_capacity),
        to_depth(pipeline.options_.queue_capacity),
        to_simplify(pipeline.options_.queue_capacity),
        to_map(pipeline.options_.queue_capacity),
        to_output(pipeline.options_.queue_capacity) {}

  bool Stopping() const { return p.stop_requested_.load() || error_stop.load(); }

  // Records a stage failure on `item`; with on_error = stop the run ends after the frames in flight.
  void Fail(Item& item, const char* stage, const std::string& what) {
    item.error_stage = stage;
    item.error = what.empty() ? "unknown error" : what;
    if (p.options_.on_error == PipelineOptions::OnError::kStop) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (fatal_error.empty()) fatal_error = std::string(stage) + " failed on frame " +
                                             std::to_string(item.frame_id) + ": " + item.error;
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
        fatal_error = std::to_string(*consecutive_failures) + " frames in a row could not be read or had an "
                      "unusable pose; last: " + what;
      }
      error_stop.store(true);
    }
  }

  void ReadLoop() {
    // In realtime mode the reader is the sensor's clock: it keeps the map's priority.
    const bool realtime = p.options_.mode == PipelineOptions::Mode::kRealtime;
    SetUpThread("semap-read", p.options_.cpu_affinity, realtime ? 0 : p.options_.feeder_nice);
    std::int64_t seq = 0;
    std::int64_t last_id = -1;
    int consecutive_failures = 0;
    std::optional<double> first_timestamp;
    std::optional<AcceptedPose> last_pose;
    std::int64_t paced = 0;
    KeyframeSchedule schedule(p.keyframe_every_frames_);
    std::shared_future<SegmentResult> current_keyframe;
    while (!Stopping()) {
      Item item;
      const auto t0 = Clock::now();
      try {
        std::optional<Frame> frame = p.reader_->Next();
        if (!frame) break;
        item.frame_id = frame->id;
        item.timestamp_s = frame->timestamp_s;
        item.world_from_cam = frame->world_from_cam;
        last_id = item.frame_id;
        const std::string pose_problem =
            frame->world_from_cam ? PoseProblem(*frame->world_from_cam, frame->timestamp_s, last_pose, p.options_)
                                  : std::string();
        if (pose_problem.empty()) {
          consecutive_failures = 0;
          if (frame->world_from_cam) {
            last_pose = AcceptedPose{frame->id, frame->timestamp_s, frame->world_from_cam->translation()};
          }
          item.frame = std::make_unique<Frame>(std::move(*frame));
        } else {
          item.world_from_cam.reset();
          FailRead(item, "pose", "frame " + std::to_string(item.frame_id) + ": " + pose_problem,
                   &consecutive_failures);
        }
      } catch (const std::exception& e) {
        item.frame_id = last_id + 1;
        last_id = item.frame_id;
        FailRead(item, kStageNames[kRead], e.what(), &consecutive_failures);
      }
      item.ms[kRead] = MsBetween(t0, Clock::now());
      ++frames_read;
      if (p.segment_ && item.frame && !AttachKeyframe(item, realtime, &schedule, &current_keyframe)) {
        ++frames_dropped;  // realtime: no keyframe labels yet (the segment queue was full)
        continue;
      }
      if (realtime) {
        // Sensor rate: the frame's own timestamp when the sequence has increasing ones, else the rate.
        double due_s = static_cast<double>(paced++) / p.options_.realtime_rate_hz;
        if (!first_timestamp) first_timestamp = item.timestamp_s;
        if (item.timestamp_s > *first_timestamp) due_s = item.timestamp_s - *first_timestamp;
        std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(due_s)));
        item.seq = seq;
        if (!to_depth.TryPush(std::move(item))) {
          ++frames_dropped;  // counted, never silent
          continue;
        }
        ++seq;
      } else {
        item.seq = seq++;
        to_depth.Push(std::move(item));
      }
    }
    if (p.segment_) to_segment.PushEnd();
    for (int w = 0; w < p.options_.depth_workers; ++w) to_depth.PushEnd();
  }

  // Gives `item` (a frame read with a usable pose, or none) the labels of its keyframe: the frame itself when
  // it is due (its left image is queued to the segment thread), else the current keyframe. Returns false
  // when there is none: realtime mode, the segment queue full and no keyframe taken yet.
  bool AttachKeyframe(Item& item, bool realtime, KeyframeSchedule* schedule,
                      std::shared_future<SegmentResult>* current_keyframe) {
    const Frame& f = *item.frame;
    const bool has_pose = f.world_from_cam.has_value();
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
        *current_keyframe = std::move(labels);
        item.keyframe = true;
      }
    }
    if (!current_keyframe->valid()) return false;
    item.keyframe_labels = *current_keyframe;
    return true;
  }

  // Segments the queued keyframes in order; every job's promise is kept (a value or the error), so no depth
  // worker waits for ever. Stops at the end marker, after every queued keyframe (frames in flight need them).
  void SegmentLoop() {
    SetUpThread("semap-segment", p.options_.cpu_affinity, p.options_.feeder_nice);
    while (auto job = to_segment.Pop()) {
      const auto t0 = Clock::now();
      try {
        auto labels = std::make_shared<KeyframeLabels>();
        labels->frame_id = job->keyframe.id;
        labels->world_from_cam = job->keyframe.world_from_cam;
        labels->labels = p.segment_->Process(job->keyframe);
        job->labels.set_value({std::move(labels), MsBetween(t0, Clock::now())});
      } catch (const std::exception& e) {
        job->labels.set_exception(std::make_exception_ptr(std::runtime_error(
            "keyframe " + std::to_string(job->keyframe.id) + ": " + e.what())));
      }
    }
  }

  void DepthLoop(DepthStage* stage) {
    SetUpThread("semap-depth", p.options_.cpu_affinity, p.options_.feeder_nice);
    while (auto item = to_depth.Pop()) {
      if (!item->failed()) {
        const auto t0 = Clock::now();
        SegmentResult keyframe;
        if (item->keyframe_labels.valid()) {
          try {
            keyframe = item->keyframe_labels.get();  // waits for the segment thread; rethrows its error
            if (item->keyframe) item->segment_ms = keyframe.ms;
          } catch (const std::exception& e) {
            Fail(*item, kSegmentStageName, e.what());
          }
          item->label_wait_ms = MsBetween(t0, Clock::now());
        }
        if (!item->failed()) {
          try {
            item->cloud = stage->Process(*item->frame, keyframe.labels.get());
          } catch (const std::exception& e) {
            Fail(*item, kStageNames[kDepth], e.what());
          }
        }
        item->ms[kDepth] = MsBetween(t0, Clock::now());
      }
      item->frame.reset();  // images are not needed any more
      item->keyframe_labels = {};  // nor the keyframe's labels
      to_simplify.Push(std::move(*item));
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
          ready.points_in = static_cast<std::int64_t>(ready.cloud.size());
          try {
            ready.cloud = p.simplify_->Process(std::move(ready.cloud), &ready.counts);
          } catch (const std::exception& e) {
            Fail(ready, kStageNames[kSimplify], e.what());
          }
          ready.ms[kSimplify] = MsBetween(t0, Clock::now());
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
        try {
          if (!item->world_from_cam) throw std::runtime_error("frame has no pose");
          item->update = p.map_->Process(item->cloud, *item->world_from_cam);
        } catch (const std::exception& e) {
          Fail(*item, kStageNames[kMap], e.what());
        }
        item->ms[kMap] = MsBetween(t0, Clock::now());
      }
      item->cloud = LabelledCloud{};
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

  // A sink that throws (e.g. its output folder became unwritable) does not stop the run: the error is
  // recorded in the summary and the sink is called again for the next frames.
  template <typename Call>
  void ForEachSink(PipelineSummary* summary, Call&& call) {
    for (auto* s : p.sinks_) {
      try {
        call(*s);
      } catch (const std::exception& e) {
        ++summary->sink_errors;
        if (summary->first_sink_error.empty()) summary->first_sink_error = e.what();
      }
    }
  }

  void OutputLoop(PipelineSummary* summary) {
    std::array<TimingStats, kNumStages> timing;
    TimingStats segment_timing;                      // keyframes only
    std::map<std::string, TimingStats> step_timing;  // "map.<step>"
    FrameStats stats;
    // The map's surface snapshots become the deltas the sinks receive here, not on the map's thread.
    MeshPublisher publisher;
    auto publish = [&](const MapUpdate& update) {
      MeshDelta delta = publisher.Publish(update);
      stats.mesh_triangles = publisher.published_triangles();
      return delta;
    };
    // The run's totals as of now: frame rate, the map's sizes (from `update`; kept as they were without one),
    // the process's memory and CPU.
    auto take_totals = [&](const MapUpdate* update) {
      stats.fps = stats.elapsed_s > 0 ? static_cast<double>(stats.frames_processed) / stats.elapsed_s : 0.0;
      if (update != nullptr) {
        stats.map_vertices = update->vertices;
        stats.map_cells = update->cells;
        stats.map_rays = update->rays;
      }
      stats.rss_mb = CurrentRssMb();
      stats.cpu_s = ProcessCpuSeconds();
    };
    while (auto item = to_output.Pop()) {
      const auto now = Clock::now();
      stats.elapsed_s = MsBetween(start, now) / 1000.0;
      stats.frames_dropped = frames_dropped.load();
      if (item->final) {
        if (item->failed()) {
          ForEachSink(summary, [&](PipelineSink& s) { s.OnFrameError(-1, item->error_stage, item->error); });
        }
        // A failed finish carries no update: the map as of the last frame is what was published.
        const MeshDelta delta = publish(item->update);
        take_totals(item->failed() ? nullptr : &item->update);
        ForEachSink(summary, [&](PipelineSink& s) { s.OnFinish(stats, delta); });
        continue;
      }
      if (item->failed()) {
        ++stats.frames_failed;
        ForEachSink(summary, [&](PipelineSink& s) { s.OnFrameError(item->frame_id, item->error_stage, item->error); });
        continue;
      }
      ++stats.frames_processed;
      stats.frame_id = item->frame_id;
      stats.timestamp_s = item->timestamp_s;
      const std::array<int, kNumStages> occupancy = {0, to_depth.size(), to_simplify.size(), to_map.size()};
      stats.stages.clear();
      auto add_step = [&](const std::string& name, double ms) {
        TimingStats& t = step_timing[name];
        t.Add(ms);
        stats.stages.push_back({name, ms, t.mean(), t.Percentile(0.5), t.Percentile(0.95), t.max(), 0});
      };
      for (int s = 0; s < kNumStages; ++s) {
        timing[s].Add(item->ms[s]);
        stats.stages.push_back({kStageNames[s], item->ms[s], timing[s].mean(), timing[s].Percentile(0.5),
                                timing[s].Percentile(0.95), timing[s].max(), occupancy[s]});
        if (s == kRead && p.segment_) {
          // The segmenter's time on this frame (0 unless it is a keyframe); the statistics are over keyframes.
          if (item->keyframe) segment_timing.Add(item->segment_ms);
          stats.stages.push_back({kSegmentStageName, item->segment_ms, segment_timing.mean(),
                                  segment_timing.Percentile(0.5), segment_timing.Percentile(0.95),
                                  segment_timing.max(), to_segment.size()});
        }
      }
      if (p.segment_) add_step(kLabelWaitStepName, item->label_wait_ms);
      for (const StepTime& step : item->update.steps) add_step(std::string(kStageNames[kMap]) + "." + step.name, step.ms);
      stats.points_in = item->points_in;
      stats.points_kept = 0;
      for (const auto& c : item->counts) stats.points_kept += c.kept;
      if (item->counts.empty()) stats.points_kept = stats.points_in;
      stats.class_counts = item->counts;
      const MeshDelta delta = publish(item->update);
      take_totals(&item->update);
      ForEachSink(summary, [&](PipelineSink& s) { s.OnFrame(stats, delta, item->world_from_cam); });
    }
    summary->final_stats = stats;
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
  const OpenCvThreads opencv_threads(options_.opencv_threads);
  if (options_.feeder_nice > 0) StartTbbWorkers();
  impl.start = Clock::now();
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
