// The streaming engine: frame reading → depth + labels (N workers) → windowed simplification →
// incremental map → sinks, each on its own thread, connected by bounded queues.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/options.h"
#include "engine/pipeline/clock.h"
#include "engine/pipeline/stages.h"

namespace semap {

struct PipelineOptions {
  enum class Mode {
    kExhaustive,  // every frame is processed; the reader blocks on a full queue (the paper's table)
    kRealtime,    // frames enter when their time stamp comes due, whether or not the engine is ready for
                  // them: the input queue keeps the newest frame, and the waiting one it replaces is dropped
  };
  enum class OnError { kSkipFrame, kStop };

  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  Mode mode = Mode::kExhaustive;
  double realtime_rate_hz = 10.0;  // KITTI: 10 Hz
  double realtime_speed = 1.0;
  int realtime_frames_in_flight = 2;
  bool realtime_label_budget = true;
  int depth_workers = 2;
  int queue_capacity = 4;
  OnError on_error = OnError::kSkipFrame;
  double max_speed_mps = 100.0;
  std::vector<int> cpu_affinity;
  int feeder_nice = 10;
  int opencv_threads = 1;
  int mesh_every_frames = 5;
  int realtime_mesh_every_frames = 1;

  // CPU ids a process can be pinned to: CPU_SETSIZE of <sched.h> (pipeline.cc checks that they agree).
  static constexpr int kCpuSetSize = 1024;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Enum("mode", &mode, {{"exhaustive", Mode::kExhaustive}, {"realtime", Mode::kRealtime}},
           "exhaustive: every frame processed (the paper's table); realtime: frames enter at their time "
           "stamps, as a camera delivers them, and the oldest waiting frame is dropped when the engine is "
           "behind");
    v.Field("realtime_rate_hz", &realtime_rate_hz,
            "realtime mode: frames are due at their time stamps, or at this rate when the sequence has none",
            Above(0));
    v.Field("realtime_speed", &realtime_speed,
            "realtime mode: frames are played at this multiple of the sensor's rate (2 = twice as fast)",
            Above(0));
    // Each frame ahead of a frame on its way to the map adds the map's time per frame to its latency; the
    // input queue meanwhile keeps the newest frame only. More frames in flight keep both depth workers busy
    // when the map is faster than the depth; fewer make the published mesh younger.
    v.Field("realtime_frames_in_flight", &realtime_frames_in_flight,
            "realtime mode: frames taken from the input queue and not yet integrated, at most (1 = a frame's "
            "depth starts once the map has integrated the one before)",
            AtLeast(1));
    // Labels are carried between keyframes by reprojection (semantics.enet_propagation); a keyframe adds the
    // segmenter's time to the CPU the frames share. On: a machine with time to spare labels more often, one
    // that is behind labels less often and maps more of the frames.
    v.Field("realtime_label_budget", &realtime_label_budget,
            "realtime mode with ENet on keyframes: keyframes as far apart as the frame budget leaves the "
            "segmenter time for (cores x frame period, less the depth, simplification and map times measured "
            "so far; at most 3 s of the sensor's time apart); off: every semantics.enet_every_frames frames, "
            "as in exhaustive mode");
    v.Field("depth_workers", &depth_workers,
            "threads running SGBM depth, the heaviest per-frame stage (frames are reordered after them)",
            In(1, 64));
    v.Field("queue_capacity", &queue_capacity,
            "exhaustive mode: frames each queue between stages holds at most (realtime mode: the input queue "
            "holds the newest frame only)",
            AtLeast(1));
    v.Enum("on_error", &on_error, {{"skip", OnError::kSkipFrame}, {"stop", OnError::kStop}},
           "a stage failing on a frame: skip the frame (counted) or stop the run (drain, write the mesh)");
    // The time between the frames is taken as at least 1 / realtime_rate_hz, so repeated timestamps do not
    // reject every frame. A frame with a non-finite or non-rigid pose is skipped and counted the same way.
    v.Field("max_speed_mps", &max_speed_mps,
            "skip (and count) a frame whose camera moved faster than this since the last accepted frame, m/s "
            "(a GPS/OXTS pose jump); 0 = no check",
            AtLeast(0));
    v.Field("cpu_affinity", &cpu_affinity, "CPU ids the engine's threads may run on, e.g. [0, 1]; [] = any",
            AtLeast(0).Below(kCpuSetSize));
    // The map thread is the critical path (its serial steps cannot use a second core, its parallel votes
    // can): on a saturated machine the scheduler should give it the CPU first. Nice 10 weighs a thread about
    // a tenth of one at 0 under Linux's scheduler; the bounded queues keep the feeders ahead, on the CPU the
    // map leaves. 200 urban frames, PS, 2 cores: 5.02 / 4.79 → 5.54 / 5.01 f/s (bench/results/frame-rate.md,
    // "The map's feeders niced").
    v.Field(
        "feeder_nice", &feeder_nice,
        "how much nicer (Linux nice steps) the threads feeding the map (segment, depth, simplify; read in "
        "exhaustive mode) run than the map's own thread, so that a saturated machine runs the map first; 0 = "
        "all alike",
        In(0, 19));
    // OpenCV runs its parallel loops (SGBM, ENet) on TBB's workers, which the map's votes share: started at
    // the map's priority (StartTbbWorkers), they ran a feeder's SGBM ahead of the map. With one thread SGBM
    // runs on the depth thread that calls it, at the feeders' priority; depth_workers keep frames in
    // parallel. 200 urban frames, PS, half resolution: map.votes 49–51 → 43 ms, 8.5–8.9 → 9.1–9.3 f/s
    // (bench/results/frame-rate.md, "What changed").
    v.Field("opencv_threads", &opencv_threads,
            "OpenCV's threads during a run (cv::setNumThreads, process-wide, restored after the run): 1 runs "
            "SGBM and ENet on the feeder thread that calls them, at its priority; more lets them use TBB's "
            "workers, which run at the map's priority; 0 = OpenCV's setting as it is",
            AtLeast(0));
    // Extracting the whole live surface and diffing it costs about as much as the votes (80 urban frames, PS,
    // half-resolution SGBM: 98 of 305 ms per frame; bench/results/frame-rate.md, "Mesh cadence"), while a
    // viewer or a logger needs the mesh at a few Hz, not at the sensor's rate. 5 is 2 Hz on a 10 Hz stream.
    v.Field(
        "mesh_every_frames", &mesh_every_frames,
        "exhaustive mode: the map extracts and publishes the mesh's change every this many frames (and at "
        "the end), integrating every frame; 1 = every frame; the final mesh is the same for any value",
        AtLeast(1));
    // A frame's latency to the published mesh is its latency to the map plus the wait for the next
    // extraction: up to this many frame periods. Extracting after each frame adds its cost to the map's
    // time a frame (bench/RESULTS.md, "Frame rate today").
    v.Field("realtime_mesh_every_frames", &realtime_mesh_every_frames,
            "realtime mode: the map extracts and publishes the mesh's change every this many frames of the "
            "sequence (and at the end); 1 = after every frame",
            AtLeast(1));
  }

  void Check() const;
  // The capacity of each queue behind the input queue in this mode (realtime_frames_in_flight or
  // queue_capacity).
  int QueueCapacity() const;
  // The mesh cadence in this mode (realtime_mesh_every_frames or mesh_every_frames).
  int MeshEveryFrames() const;
};

// Why a frame of the sequence was never integrated (FrameStats::dropped_by_reason names them).
enum class DropReason {
  kBehind,            // a newer frame took its place in the full input queue
  kNoKeyframeLabels,  // no keyframe had been taken for labels yet (the segment queue was full)
  kLost,              // the reader lost it (FrameReader::TakeLost: a split run's frame that never arrived)
};
const char* DropReasonName(DropReason reason);

using DepthStageFactory = std::function<std::unique_ptr<DepthStage>()>;

struct PipelineSummary {
  FrameStats final_stats;  // totals, fps, per-stage timing
  std::int64_t frames_read = 0;
  bool stopped_early = false;    // RequestStop() or a stage error with on_error = stop
  std::string fatal_error;       // the error that stopped the run, if any
  std::int64_t sink_errors = 0;  // exceptions thrown by sinks (the run went on)
  std::string first_sink_error;
};

// Owns its stages and threads. Run() may be called once. RequestStop() is thread-safe and
// async-signal-safe (an atomic store), so a SIGINT handler may call it.
class Pipeline {
 public:
  Pipeline(const PipelineOptions& options, std::unique_ptr<FrameReader> reader,
           DepthStageFactory depth_factory, std::unique_ptr<SimplifyStage> simplify,
           std::unique_ptr<MapStage> map);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Sinks are not owned and must outlive Run().
  void AddSink(PipelineSink* sink) { sinks_.push_back(sink); }

  // Optional, before Run(): the clock frames are paced and latencies measured by (not owned; must outlive
  // Run()). SteadyClock otherwise.
  void SetClock(PipelineClock* clock) { clock_ = clock; }

  // Optional, before Run(): labels from `segment` on its own thread, on keyframes only (KeyframeSchedule with
  // `keyframe_every_frames`, decided by the reader in frame order: deterministic). A keyframe's left image is
  // queued to the segment thread (bounded queue of queue_capacity keyframes) when the frame is read, so the
  // segmenter runs concurrently with the depth workers; each frame's depth stage then receives its keyframe's
  // labels (DepthStage::Process), waiting for them if the segmenter is behind. In realtime mode a keyframe
  // that finds the segment queue full is not taken (the next frame is due); a frame with no keyframe yet is
  // dropped and counted. A segmenter error fails the frames of that keyframe (stage "segment").
  // Reported per frame: stage "segment" (the keyframe's time, on keyframes; the queue of keyframes) and step
  // "depth.label_wait" (time the depth worker waited for its keyframe's labels).
  void SetSegmentStage(std::unique_ptr<SegmentStage> segment, int keyframe_every_frames);

  // Streams the whole sequence; returns when every frame read has been processed or failed, after a stop
  // request (the frames in flight are drained), or when a stage failed with on_error = stop.
  PipelineSummary Run();

  void RequestStop() { stop_requested_.store(true); }
  // RequestStop() was called (thread-safe): a reader that waits for frames may give up waiting.
  bool StopRequested() const { return stop_requested_.load(); }

 private:
  struct Impl;
  PipelineOptions options_;
  std::unique_ptr<FrameReader> reader_;
  DepthStageFactory depth_factory_;
  std::unique_ptr<SimplifyStage> simplify_;
  std::unique_ptr<MapStage> map_;
  std::unique_ptr<SegmentStage> segment_;  // optional
  int keyframe_every_frames_ = 1;
  std::vector<PipelineSink*> sinks_;
  SteadyClock steady_clock_;
  PipelineClock* clock_ = &steady_clock_;
  std::atomic<bool> stop_requested_{false};
};

// Resident set size of this process in MiB (Linux /proc/self/statm), 0 if unknown.
double CurrentRssMb();
// CPU time used so far by this process, all threads, in seconds.
double ProcessCpuSeconds();

}  // namespace semap
