// Realtime pacing, the drop policy and the latency figures, against a clock the test moves (ManualClock):
// frames are due when the test says, stages take the time the test gives them, and no result depends on the
// wall clock.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <set>
#include <thread>

#include "engine/core/check.h"
#include "engine/core/mesh_delta.h"
#include "engine/pipeline/internal/admission_queue.h"
#include "engine/pipeline/internal/frame_pacer.h"
#include "engine/pipeline/pipeline.h"
#include "tests/engine/pipeline/manual_clock.h"

namespace semap {
namespace {

using test::ManualClock;

constexpr double kFramePeriodS = 0.1;
constexpr double kStartS = 100.0;  // ManualClock's time when the run starts
constexpr double kTolMs = 1e-6;

double DueS(int frame) { return kStartS + kFramePeriodS * frame; }

class StageLog;

// Frames 0..n-1 at kFramePeriodS, moving along z. Reading frame k takes read_s[k] on the clock (0 if absent),
// once the depth stage (`depth_log`) has taken every earlier frame: a newer frame evicts a waiting one.
class ClockedReader : public FrameReader {
 public:
  ClockedReader(int n, ManualClock* clock, std::map<std::int64_t, double> read_s, StageLog* depth_log)
      : n_(n), clock_(clock), read_s_(std::move(read_s)), depth_log_(depth_log) {}
  std::optional<Frame> Next() override {
    if (next_ >= n_) return std::nullopt;
    Frame f;
    f.id = next_++;
    f.timestamp_s = kFramePeriodS * static_cast<double>(f.id);
    f.world_from_cam = Pose3d(Eigen::Translation3d(0, 0, static_cast<double>(f.id)));
    if (auto it = read_s_.find(f.id); it != read_s_.end()) SlowRead(f.id, it->second);
    return f;
  }

 private:
  void SlowRead(std::int64_t frame_id, double read_s);
  int n_;
  ManualClock* clock_;
  std::map<std::int64_t, double> read_s_;
  StageLog* depth_log_;
  std::int64_t next_ = 0;
};

// What a stage saw, for the test thread to wait on.
class StageLog {
 public:
  // `keyframe_id`: the keyframe whose labels the frame took (-1: none).
  void Add(std::int64_t frame_id, std::int64_t keyframe_id = -1) {
    std::lock_guard<std::mutex> lock(mutex_);
    ids_.push_back(frame_id);
    keyframe_of_[frame_id] = keyframe_id;
    changed_.notify_all();
  }
  std::map<std::int64_t, std::int64_t> keyframe_of() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return keyframe_of_;
  }
  bool WaitForCount(std::size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(30), [&] { return ids_.size() >= n; });
  }
  std::vector<std::int64_t> ids() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return ids_;
  }
  bool WaitForId(std::int64_t frame_id) const {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(30),
                             [&] { return std::find(ids_.begin(), ids_.end(), frame_id) != ids_.end(); });
  }

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::vector<std::int64_t> ids_;
  std::map<std::int64_t, std::int64_t> keyframe_of_;
};

void ClockedReader::SlowRead(std::int64_t frame_id, double read_s) {
  EXPECT_TRUE(depth_log_->WaitForCount(static_cast<std::size_t>(frame_id)));
  clock_->Advance(read_s);
}

// One point per frame; takes `depth_s` on the clock.
class ClockedDepth : public DepthStage {
 public:
  ClockedDepth(ManualClock* clock, double depth_s, StageLog* log)
      : clock_(clock), depth_s_(depth_s), log_(log) {}
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* keyframe) override {
    log_->Add(frame.id, keyframe != nullptr ? keyframe->frame_id : -1);
    clock_->Advance(depth_s_);
    LabelledCloud c;
    c.positions_world.emplace_back(0, 0, frame.id);
    c.labels.assign(1, 0);
    c.camera_index.assign(1, 0);
    c.camera_centers_world = {frame.world_from_cam->translation()};
    c.camera_frame_ids = {frame.id};
    return c;
  }

 private:
  ManualClock* clock_;
  double depth_s_;
  StageLog* log_;
};

// A segmenter that labels keyframes below `gate_from` at once and holds the others until the test opens it.
class GatedSegment : public SegmentStage {
 public:
  explicit GatedSegment(std::int64_t gate_from) : gate_from_(gate_from) {}
  cv::Mat Process(const Frame& keyframe) override {
    std::unique_lock<std::mutex> lock(mutex_);
    opened_.wait(lock, [&] { return keyframe.id < gate_from_ || open_; });
    return cv::Mat(1, 1, CV_8UC1, cv::Scalar(0));
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    opened_.notify_all();
  }

 private:
  std::int64_t gate_from_;
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

class PassSimplify : public SimplifyStage {
 public:
  LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>*) override { return cloud; }
};

// One live triangle per frame, its surface extracted every `mesh_every` frames; takes `map_s` on the clock.
// Closed, it holds each frame until the test opens it.
class ClockedMap : public MapStage {
 public:
  ClockedMap(ManualClock* clock, double map_s, int mesh_every, StageLog* log, bool closed = false)
      : clock_(clock), map_s_(map_s), mesh_every_(mesh_every), log_(log), closed_(closed) {}
  MapUpdate Process(const LabelledCloud& cloud, const Pose3d&) override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      opened_.wait(lock, [&] { return !closed_; });
    }
    clock_->Advance(map_s_);
    MapUpdate u;
    u.frame_id = cloud.camera_frame_ids.at(0);
    const auto first = static_cast<std::uint32_t>(live_.mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      live_.mesh.vertices.push_back(Eigen::Vector3d(double(u.frame_id), double(k), 0.0));
      live_.vertex_ids.push_back(next_vertex_++);
    }
    live_.mesh.triangles.push_back({first, first + 1, first + 2});
    if (++frames_ % mesh_every_ == 0) u.mesh = MeshSnapshot{live_, {}};
    log_->Add(u.frame_id);
    return u;
  }
  MapUpdate Finish() override {
    MapUpdate u;
    u.mesh = MeshSnapshot{live_, {}};
    return u;
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = false;
    opened_.notify_all();
  }

 private:
  ManualClock* clock_;
  double map_s_;
  int mesh_every_;
  StageLog* log_;
  std::mutex mutex_;
  std::condition_variable opened_;
  bool closed_;
  IdentifiedMesh live_;
  VertexId next_vertex_ = 0;
  int frames_ = 0;
};

// What the sinks were told, and the mesh a subscriber rebuilds from the deltas.
class LogSink : public PipelineSink {
 public:
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>&) override {
    frames.push_back(stats);
    mesh.Apply(delta);
    log.Add(stats.frame_id);
  }
  void OnFrameDropped(std::int64_t frame_id, double, const std::string& reason) override {
    dropped.emplace_back(frame_id, reason);
  }
  void OnFinish(const FrameStats& stats, const MeshDelta& delta) override {
    final_stats = stats;
    mesh.Apply(delta);
  }
  std::vector<FrameStats> frames;
  std::vector<std::pair<std::int64_t, std::string>> dropped;
  FrameStats final_stats;
  MeshAccumulator mesh;
  StageLog log;
};

PipelineOptions RealtimeOptions() {
  PipelineOptions options;
  options.mode = PipelineOptions::Mode::kRealtime;
  options.realtime_frames_in_flight = 1;
  options.depth_workers = 1;
  options.feeder_nice = 0;
  options.realtime_label_budget = false;  // keyframes every Setup::keyframe_every frames, as the tests say
  return options;
}

// A pipeline of the clocked stages, run on its own thread.
struct ClockedRun {
  ManualClock clock;
  StageLog depth_log;
  StageLog map_log;
  LogSink sink;
  ClockedMap* map = nullptr;
  std::unique_ptr<Pipeline> pipeline;
  PipelineSummary summary;
  std::thread thread;

  // How the clocked stages behave: seconds each takes on the clock, the map's mesh cadence, whether the map
  // starts closed, the frames whose read takes time, and an optional segment stage on keyframes.
  struct Setup {
    int frames = 6;
    double depth_s = 0.0;
    double map_s = 0.0;
    int mesh_every = 1;
    bool map_closed = false;
    std::map<std::int64_t, double> read_s;
    std::unique_ptr<SegmentStage> segment;
    int keyframe_every = 1;
  };

  ClockedRun(PipelineOptions options, Setup setup) {
    auto m = std::make_unique<ClockedMap>(&clock, setup.map_s, setup.mesh_every, &map_log, setup.map_closed);
    map = m.get();
    pipeline = std::make_unique<Pipeline>(
        options, std::make_unique<ClockedReader>(setup.frames, &clock, std::move(setup.read_s), &depth_log),
        [this, depth_s = setup.depth_s] {
          return std::make_unique<ClockedDepth>(&clock, depth_s, &depth_log);
        },
        std::make_unique<PassSimplify>(), std::move(m));
    if (setup.segment) pipeline->SetSegmentStage(std::move(setup.segment), setup.keyframe_every);
    pipeline->SetClock(&clock);
    pipeline->AddSink(&sink);
    thread = std::thread([this] { summary = pipeline->Run(); });
  }
  // Lets the reader deliver the frame due at `due_s`, once it waits for it.
  void Deliver(double due_s) {
    ASSERT_TRUE(clock.WaitForSleeperUntil(due_s)) << "the reader never waited for " << due_s;
    clock.AdvanceTo(due_s);
  }
  void Join() { thread.join(); }
};

TEST(AdmissionQueue, AFullQueueEvictsItsOldestItemAndPopsAreNumberedWithoutGaps) {
  pipeline_internal::AdmissionQueue<int> queue(2);
  EXPECT_FALSE(queue.PushEvictingOldest(1).has_value());
  EXPECT_FALSE(queue.PushEvictingOldest(2).has_value());
  EXPECT_EQ(queue.PushEvictingOldest(3), std::optional<int>(1));
  EXPECT_EQ(queue.PushEvictingOldest(4), std::optional<int>(2));
  queue.PushEnd();
  EXPECT_EQ(queue.PushEvictingOldest(5), std::optional<int>(3));  // the end marker stays
  auto a = queue.Pop();
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->item, 4);
  EXPECT_EQ(a->order, 0);
  EXPECT_FALSE(queue.Pop().has_value());  // the end marker, in its place
  auto b = queue.Pop();
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->item, 5);
  EXPECT_EQ(b->order, 1);
}

TEST(FramePacer, FramesAreDueAtTheirTimeStampsOverTheSpeedOrAtTheRateWithout) {
  pipeline_internal::FramePacer pacer(5.0, 10.0, 2.0);
  EXPECT_DOUBLE_EQ(pacer.NextDueS(10.0), 5.0);
  EXPECT_DOUBLE_EQ(pacer.NextDueS(10.1), 5.05);
  EXPECT_DOUBLE_EQ(pacer.NextDueS(10.5), 5.25);
  pipeline_internal::FramePacer no_stamps(0.0, 10.0, 1.0);
  EXPECT_DOUBLE_EQ(no_stamps.NextDueS(0.0), 0.0);
  EXPECT_DOUBLE_EQ(no_stamps.NextDueS(0.0), 0.1);
  EXPECT_DOUBLE_EQ(no_stamps.NextDueS(0.0), 0.2);
}

// Each frame enters when it is due and not before; its latency per step is the time the stages took from
// then, on the pipeline's clock: depth 20 ms, map 30 ms, published with its own mesh change.
TEST(PipelineRealtime, FramesEnterWhenDueAndTheirLatencyIsMeasuredFromThen) {
  constexpr int kFrames = 6;
  ClockedRun run(RealtimeOptions(), {.frames = kFrames, .depth_s = 0.020, .map_s = 0.030});
  for (int k = 1; k < kFrames; ++k) {
    ASSERT_TRUE(run.sink.log.WaitForCount(k));  // frame k-1 published
    ASSERT_TRUE(run.clock.WaitForSleeperUntil(DueS(k)));
    EXPECT_EQ(run.depth_log.ids().size(), static_cast<std::size_t>(k)) << "frame " << k << " entered early";
    run.Deliver(DueS(k));
  }
  run.Join();
  ASSERT_EQ(run.sink.frames.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    const FrameLatency& l = run.sink.frames[k].latency;
    EXPECT_EQ(run.sink.frames[k].frame_id, k);
    EXPECT_NEAR(l.late_ms, 0.0, kTolMs);
    EXPECT_NEAR(l.depth_ms, 20.0, kTolMs);
    EXPECT_NEAR(l.labels_ms, 20.0, kTolMs);  // no segment stage: labelled with the depth
    EXPECT_NEAR(l.map_ms, 50.0, kTolMs);
    EXPECT_NEAR(l.published_ms, 50.0, kTolMs);
  }
  const FrameStats& s = run.summary.final_stats;
  EXPECT_EQ(s.frames_processed, kFrames);
  EXPECT_EQ(s.frames_dropped, 0);
  ASSERT_EQ(s.latencies.size(), 4u);
  EXPECT_EQ(s.latencies[3].name, "published");
  EXPECT_NEAR(s.latencies[3].p95_ms, 50.0, kTolMs);
  EXPECT_NEAR(s.latencies[3].max_ms, 50.0, kTolMs);
}

// A frame whose map update extracts no surface is published with the next frame's mesh change: its latency
// to the published mesh runs until then, and the sinks hear of it only then, in frame order.
TEST(PipelineRealtime, AFrameWithoutAMeshChangeIsPublishedWithTheNextOne) {
  constexpr int kFrames = 6;
  ClockedRun run(RealtimeOptions(), {.frames = kFrames, .depth_s = 0.020, .map_s = 0.030, .mesh_every = 2});
  for (int k = 1; k < kFrames; ++k) {
    // After an odd frame the sink has heard of it; after an even one only the map has seen it.
    ASSERT_TRUE(k % 2 == 0 ? run.sink.log.WaitForCount(k) : run.map_log.WaitForCount(k));
    run.Deliver(DueS(k));
  }
  run.Join();
  ASSERT_EQ(run.sink.frames.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    const FrameLatency& l = run.sink.frames[k].latency;
    EXPECT_EQ(run.sink.frames[k].frame_id, k);
    // Frames 1, 3, 5 extract the surface; 0, 2, 4 wait for it, a frame period and the next frame's stages.
    EXPECT_NEAR(l.published_ms, k % 2 == 1 ? 50.0 : 150.0, kTolMs) << k;
    // An even frame's map step may be stamped after the test moved the clock on (it waits for the map
    // stage only): at least its stages' time.
    if (k % 2 == 1) {
      EXPECT_NEAR(l.map_ms, 50.0, kTolMs) << k;
    } else {
      EXPECT_GE(l.map_ms, 50.0 - kTolMs) << k;
    }
  }
  EXPECT_EQ(run.sink.mesh.ToMesh().num_triangles(), static_cast<std::size_t>(kFrames));
}

// A frame whose read ends after its due time enters late, and its latency counts from when it was due.
TEST(PipelineRealtime, AFrameReadAfterItWasDueEntersLateAndCountsItsLatencyFromItsDueTime) {
  constexpr int kFrames = 6;
  ClockedRun run(RealtimeOptions(), {.frames = kFrames, .read_s = {{3, 0.150}}});
  for (int k : {1, 2, 4, 5}) {  // frame 3 is read at 0.35 s, past its due time: the reader never waits for it
    ASSERT_TRUE(run.sink.log.WaitForCount(k));
    run.Deliver(DueS(k));
  }
  run.Join();
  ASSERT_EQ(run.sink.frames.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_NEAR(run.sink.frames[k].latency.late_ms, k == 3 ? 50.0 : 0.0, kTolMs) << k;
  }
  EXPECT_GE(run.sink.frames[3].latency.published_ms, 50.0 - kTolMs);
}

// A map that falls behind: the input queue keeps the newest frame, each frame it evicts is dropped with its
// reason, the newest frame is integrated, and a subscriber still rebuilds every published change in order.
TEST(PipelineRealtime, ABusyMapDropsTheOldestWaitingFramesAndCountsEachWithItsReason) {
  // Frames 0..kHeld-1 are delivered while the map holds its first frame; once the reader waits for frame
  // kHeld (it has handed on every earlier one), the map lets go.
  constexpr int kHeld = 20;
  constexpr int kFrames = kHeld + 1;
  // One frame in flight (RealtimeOptions): the map's. The input queue holds the newest one behind it.
  ClockedRun run(RealtimeOptions(), {.frames = kFrames, .map_closed = true});
  ASSERT_TRUE(run.depth_log.WaitForCount(1));  // frame 0 is on its way to the map, which holds it
  for (int k = 1; k < kHeld; ++k) run.Deliver(DueS(k));
  ASSERT_TRUE(run.clock.WaitForSleeperUntil(DueS(kHeld)));
  run.map->Open();
  // Frame kHeld comes once the depth worker has taken the newest held frame (else it would take its place).
  ASSERT_TRUE(run.depth_log.WaitForId(kHeld - 1));
  run.Deliver(DueS(kHeld));
  run.Join();
  const FrameStats& s = run.summary.final_stats;
  EXPECT_EQ(run.summary.frames_read, kFrames);
  EXPECT_EQ(s.frames_processed + s.frames_dropped, kFrames);
  std::vector<std::int64_t> integrated;
  for (const FrameStats& f : run.sink.frames) integrated.push_back(f.frame_id);
  // The frame the map held, the newest held frame, and the one after.
  EXPECT_EQ(integrated, (std::vector<std::int64_t>{0, kHeld - 1, kHeld}));
  ASSERT_EQ(run.sink.dropped.size(), static_cast<std::size_t>(s.frames_dropped));
  EXPECT_EQ(s.frames_dropped, kFrames - 3);
  // Every reason is listed, the ones that did not happen with 0.
  const std::vector<std::pair<std::string, std::int64_t>> by_reason = {
      {"behind", s.frames_dropped}, {"no_keyframe_labels", 0}, {"lost", 0}};
  EXPECT_EQ(s.dropped_by_reason, by_reason);
  for (std::size_t i = 0; i < run.sink.dropped.size(); ++i) {
    EXPECT_EQ(run.sink.dropped[i].second, "behind");
    if (i > 0) {
      EXPECT_GT(run.sink.dropped[i].first, run.sink.dropped[i - 1].first);  // oldest first
    }
  }
  EXPECT_EQ(run.sink.mesh.ToMesh().num_triangles(), static_cast<std::size_t>(s.frames_processed));
}

// Realtime: a frame whose keyframe is still being segmented takes the labels of the newest keyframe that were
// ready when it was read, instead of waiting: frames 2-5 go through with keyframe 0's labels while the
// segmenter still holds keyframe 2.
TEST(PipelineRealtime, AFrameTakesTheNewestReadyKeyframesLabelsInsteadOfWaiting) {
  constexpr int kFrames = 6;
  auto segment = std::make_unique<GatedSegment>(/*gate_from=*/2);
  GatedSegment* gate = segment.get();
  ClockedRun run(RealtimeOptions(), {.frames = kFrames, .segment = std::move(segment), .keyframe_every = 2});
  for (int k = 1; k < kFrames; ++k) {
    ASSERT_TRUE(run.sink.log.WaitForCount(k));  // frame k-1 published
    run.Deliver(DueS(k));
  }
  ASSERT_TRUE(run.sink.log.WaitForCount(kFrames));  // every frame published, keyframe 2 still held
  gate->Open();
  run.Join();
  const auto keyframe_of = run.depth_log.keyframe_of();
  EXPECT_EQ(keyframe_of.at(0), 0);  // nothing was ready: the first keyframe is waited for
  EXPECT_EQ(keyframe_of.at(1), 0);
  for (int k = 2; k < kFrames; ++k) EXPECT_EQ(keyframe_of.at(k), 0) << k;
  EXPECT_EQ(run.summary.final_stats.frames_processed, kFrames);
}

// A segmenter that records which frames it was given as keyframes.
class RecordingSegment : public SegmentStage {
 public:
  cv::Mat Process(const Frame& keyframe) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ids_.insert(keyframe.id);
    }
    recorded_.notify_all();
    return cv::Mat(1, 1, CV_8UC1, cv::Scalar(0));
  }
  std::set<std::int64_t> ids() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return ids_;
  }
  // Waits (at most a generous bound, never a fixed sleep) until keyframe `id` reached the segmenter.
  bool WaitFor(std::int64_t id) {
    std::unique_lock<std::mutex> lock(mutex_);
    return recorded_.wait_for(lock, std::chrono::seconds(30), [&] { return ids_.count(id) > 0; });
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable recorded_;
  std::set<std::int64_t> ids_;
};

// With the label budget, a machine with time to spare makes keyframes far more often than
// semantics.enet_every_frames says once each cost has been measured; without, every 6th frame is a
// keyframe. The budget measures the stages on the pipeline's clock, which this test holds still between
// frames: every stage costs nothing, so every frame after the first measured one is a keyframe, however
// loaded the machine is. (Which keyframe's labels a frame then uses depends on whether its own were ready.)
TEST(PipelineRealtime, TheLabelBudgetLabelsMoreOftenWhenTimeIsLeft) {
  constexpr int kFrames = 12;
  for (const bool budget : {true, false}) {
    SCOPED_TRACE(budget ? "budget" : "every 6 frames");
    PipelineOptions options = RealtimeOptions();
    options.realtime_label_budget = budget;
    options.cpu_affinity = {0, 1};  // two cores, whatever the machine has
    auto segment = std::make_unique<RecordingSegment>();
    RecordingSegment* segmenter = segment.get();
    ClockedRun run(options, {.frames = kFrames, .segment = std::move(segment), .keyframe_every = 6});
    for (int k = 1; k < kFrames; ++k) {
      ASSERT_TRUE(run.sink.log.WaitForCount(k));  // frame k-1 published: its costs are measured
      // The segmenter took the keyframe it was expected to have been given (so the one-job queue to it is
      // free again, however slowly its thread is scheduled): every frame with the budget, every 6th without.
      if (budget || (k - 1) % 6 == 0) ASSERT_TRUE(segmenter->WaitFor(k - 1)) << k - 1;
      run.Deliver(DueS(k));
    }
    run.Join();
    const std::set<std::int64_t> keyframes = segmenter->ids();
    if (budget) {
      std::set<std::int64_t> every_frame;
      for (int k = 0; k < kFrames; ++k) every_frame.insert(k);
      EXPECT_EQ(keyframes, every_frame);
    } else {
      EXPECT_EQ(keyframes, (std::set<std::int64_t>{0, 6}));
    }
    EXPECT_EQ(run.summary.final_stats.frames_processed, kFrames);
  }
}

// A stop request while the reader waits for a frame's due time ends the run at once: the frames delivered
// are integrated, the one not yet due was never read as far as the run's figures go.
TEST(PipelineRealtime, AStopWhileAFrameIsNotYetDueEndsTheRunWithEveryFrameCounted) {
  ClockedRun run(RealtimeOptions(), {.frames = 100});
  ASSERT_TRUE(run.sink.log.WaitForCount(1));
  run.Deliver(DueS(1));
  ASSERT_TRUE(run.sink.log.WaitForCount(2));
  ASSERT_TRUE(run.clock.WaitForSleeperUntil(DueS(2)));
  run.pipeline->RequestStop();
  run.Join();
  const PipelineSummary& summary = run.summary;
  EXPECT_TRUE(summary.stopped_early);
  EXPECT_EQ(summary.frames_read, 2);
  EXPECT_EQ(summary.final_stats.frames_processed, 2);
  EXPECT_EQ(summary.final_stats.frames_dropped + summary.final_stats.frames_failed, 0);
}

// A segmenter that cannot prepare on the first frame (its first forward pass throws) does not stop the run:
// the frames are labelled as they come.
TEST(PipelineRealtime, AStageThatCannotPrepareDoesNotStopTheRun) {
  class FailingPrepare : public GatedSegment {
   public:
    FailingPrepare() : GatedSegment(/*gate_from=*/1000) {}
    void Prepare(const Frame&) override { throw std::runtime_error("no network"); }
  };
  ClockedRun run(RealtimeOptions(), {.frames = 2, .segment = std::make_unique<FailingPrepare>()});
  ASSERT_TRUE(run.sink.log.WaitForCount(1));
  run.Deliver(DueS(1));
  run.Join();
  EXPECT_EQ(run.summary.final_stats.frames_processed, 2);
  EXPECT_TRUE(run.summary.fatal_error.empty());
}

// Exhaustive runs measure latency from each frame's read: every frame is integrated, none is late, and each
// step's latency covers at least the stages' own time.
TEST(PipelineBatch, LatencyIsMeasuredFromEachFramesRead) {
  PipelineOptions options;
  options.depth_workers = 1;
  options.feeder_nice = 0;
  ClockedRun run(options, {.frames = 8, .depth_s = 0.020, .map_s = 0.030});
  run.Join();
  ASSERT_EQ(run.sink.frames.size(), 8u);
  for (const FrameStats& f : run.sink.frames) {
    EXPECT_EQ(f.latency.late_ms, 0.0);
    EXPECT_GE(f.latency.depth_ms, 20.0 - kTolMs);
    EXPECT_GE(f.latency.map_ms, f.latency.depth_ms + 30.0 - kTolMs);
    EXPECT_GE(f.latency.published_ms, f.latency.map_ms);
  }
  EXPECT_EQ(run.summary.final_stats.frames_dropped, 0);
}

TEST(PipelineOptions, RealtimeSpeedAndQueueAreChecked) {
  PipelineOptions options;
  options.realtime_speed = 0.0;
  EXPECT_THROW(options.Check(), InvalidOption);
  options = PipelineOptions{};
  options.realtime_frames_in_flight = 0;
  EXPECT_THROW(options.Check(), InvalidOption);
  options = PipelineOptions{};
  options.realtime_mesh_every_frames = 0;
  EXPECT_THROW(options.Check(), InvalidOption);
}

// Each mode has its own mesh cadence: the sensor's rate wants a young mesh, a batch run a cheap one.
TEST(PipelineOptions, EachModeHasItsMeshCadence) {
  PipelineOptions options;
  options.mesh_every_frames = 5;
  options.realtime_mesh_every_frames = 2;
  EXPECT_EQ(options.MeshEveryFrames(), 5);
  options.mode = PipelineOptions::Mode::kRealtime;
  EXPECT_EQ(options.MeshEveryFrames(), 2);
  EXPECT_EQ(PipelineOptions{}.realtime_mesh_every_frames, 1);
}

}  // namespace
}  // namespace semap
