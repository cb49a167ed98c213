#include "engine/pipeline/pipeline.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <map>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <set>
#include <thread>
#include <utility>

#include "engine/core/check.h"
#include "engine/core/parallel.h"

namespace semap {
namespace {

using namespace std::chrono_literals;

// Frames 0..n-1, 0.1 s apart, camera moving along z. Throws on the ids in `bad`.
class FakeReader : public FrameReader {
 public:
  FakeReader(int n, std::set<std::int64_t> bad = {}) : n_(n), bad_(std::move(bad)) {}
  std::optional<Frame> Next() override {
    if (next_ >= n_) return std::nullopt;
    const std::int64_t id = next_++;
    if (bad_.count(id)) throw std::runtime_error("corrupt frame " + std::to_string(id));
    Frame f;
    f.id = id;
    f.timestamp_s = 0.1 * static_cast<double>(id);
    f.world_from_cam = Pose3d(Eigen::Translation3d(0, 0, static_cast<double>(id)));
    return f;
  }

 private:
  int n_;
  std::int64_t next_ = 0;
  std::set<std::int64_t> bad_;
};

// Frame k gives k + 10 points; takes a frame-dependent time so that parallel workers finish out of order.
class FakeDepth : public DepthStage {
 public:
  explicit FakeDepth(std::set<std::int64_t> bad = {}) : bad_(std::move(bad)) {}
  LabelledCloud Process(const Frame& frame, const KeyframeLabels*) override {
    std::this_thread::sleep_for(std::chrono::microseconds(300 * ((frame.id * 7) % 5)));
    if (bad_.count(frame.id)) throw std::runtime_error("no valid disparity");
    LabelledCloud c;
    for (int i = 0; i < frame.id + 10; ++i) c.positions_world.emplace_back(i, 0, frame.id);
    c.labels.assign(c.size(), static_cast<Label>(frame.id % 3));
    c.camera_index.assign(c.size(), 0);
    c.camera_centers_world = {frame.world_from_cam->translation()};
    c.camera_frame_ids = {frame.id};
    return c;
  }

 private:
  std::set<std::int64_t> bad_;
};

// Keeps every other point; checks frames arrive in order.
class FakeSimplify : public SimplifyStage {
 public:
  LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) override {
    const std::int64_t frame = cloud.camera_frame_ids.at(0);
    EXPECT_GT(frame, last_frame_) << "simplifier got frames out of order";
    last_frame_ = frame;
    std::vector<std::uint32_t> keep;
    for (std::uint32_t i = 0; i < cloud.size(); i += 2) keep.push_back(i);
    counts->push_back({cloud.labels.at(0), static_cast<std::int64_t>(cloud.size()),
                       static_cast<std::int64_t>(keep.size())});
    return cloud.Subset(keep);
  }
  std::int64_t last_frame_ = -1;
};

// One more live triangle per frame, one finalised triangle at the end; optionally slow.
class FakeMap : public MapStage {
 public:
  explicit FakeMap(std::chrono::milliseconds delay = 0ms, bool finish_throws = false)
      : delay_(delay), finish_throws_(finish_throws) {}
  MapUpdate Process(const LabelledCloud& cloud, const Pose3d& world_from_cam) override {
    std::this_thread::sleep_for(delay_);
    MapUpdate u;
    u.frame_id = cloud.camera_frame_ids.at(0);
    AddTriangle(&live_);
    u.mesh = MeshSnapshot{live_, {}};
    u.vertices = static_cast<std::int64_t>(cloud.size());
    return u;
  }
  MapUpdate Finish() override {
    if (finish_throws_) throw std::runtime_error("final mesh extraction failed");
    MapUpdate u;
    u.mesh = MeshSnapshot{live_, {}};
    AddTriangle(&u.mesh->finalised);
    return u;
  }

 private:
  // A triangle of three new vertices.
  void AddTriangle(IdentifiedMesh* m) {
    const auto first = static_cast<std::uint32_t>(m->mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      m->mesh.vertices.push_back(Eigen::Vector3d(double(next_vertex_), double(k), 0.0));
      m->vertex_ids.push_back(next_vertex_++);
    }
    m->mesh.triangles.push_back({first, first + 1, first + 2});
  }
  std::chrono::milliseconds delay_;
  bool finish_throws_ = false;
  IdentifiedMesh live_;
  VertexId next_vertex_ = 0;
};

class RecordingSink : public PipelineSink {
 public:
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override {
    frames.push_back(stats.frame_id);
    last = stats;
    triangles += delta.added_triangle_ids.size();
    EXPECT_TRUE(pose.has_value());
  }
  void OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) override {
    errors.push_back({frame_id, stage + ": " + what});
  }
  void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) override {
    ++finishes;
    last = stats;
    triangles += final_delta.added_triangle_ids.size();
  }
  std::vector<std::int64_t> frames;
  std::vector<std::pair<std::int64_t, std::string>> errors;
  FrameStats last;
  size_t triangles = 0;
  int finishes = 0;
};

PipelineSummary RunPipeline(PipelineOptions options, std::unique_ptr<FrameReader> reader, RecordingSink* sink,
                            std::set<std::int64_t> bad_depth = {},
                            std::chrono::milliseconds map_delay = 0ms) {
  Pipeline pipeline(
      options, std::move(reader), [bad_depth] { return std::make_unique<FakeDepth>(bad_depth); },
      std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>(map_delay));
  pipeline.AddSink(sink);
  return pipeline.Run();
}

// Runs `pipeline`, asking it to stop (as SIGINT / SIGTERM do) after `delay`.
PipelineSummary RunAndStopAfter(Pipeline& pipeline, std::chrono::milliseconds delay) {
  std::thread stopper([&] {
    std::this_thread::sleep_for(delay);
    pipeline.RequestStop();
  });
  PipelineSummary summary = pipeline.Run();
  stopper.join();
  return summary;
}

// The calling thread's nice value.
int ThreadNice() { return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid))); }

// The nice values of TBB's threads, every worker taking part. The wait bounds how long the workers may take
// to start (it returns as soon as all have): on a loaded machine under TSan one took over 500 ms.
std::set<int> NicesOfTbbThreads() {
  std::mutex mutex;
  std::set<int> nices;
  std::set<std::thread::id> ids;
  const bool each_once = OnEveryThread(5s, [&] {
    std::lock_guard<std::mutex> lock(mutex);
    nices.insert(ThreadNice());
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_TRUE(each_once);
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()))
      << "every TBB thread took part";
  return nices;
}

// A depth stage that records its thread's nice value and, as OpenCV's SGBM does, runs a TBB loop (from a
// niced thread: the first TBB use of the process when this test runs first).
class NiceRecordingDepth : public FakeDepth {
 public:
  explicit NiceRecordingDepth(std::atomic<int>* nice) : nice_(nice) {}
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* labels) override {
    nice_->store(ThreadNice());
    NicesOfTbbThreads();
    return FakeDepth::Process(frame, labels);
  }

 private:
  std::atomic<int>* nice_;
};

// A map stage that records its thread's nice value and those of the threads running its parallel loops.
class NiceRecordingMap : public FakeMap {
 public:
  NiceRecordingMap(int* nice, std::set<int>* loop_nices) : nice_(nice), loop_nices_(loop_nices) {}
  MapUpdate Process(const LabelledCloud& cloud, const Pose3d& world_from_cam) override {
    *nice_ = ThreadNice();
    const std::set<int> nices = NicesOfTbbThreads();
    loop_nices_->insert(nices.begin(), nices.end());
    return FakeMap::Process(cloud, world_from_cam);
  }

 private:
  int* nice_;
  std::set<int>* loop_nices_;
};

// First in this file (see NiceRecordingDepth). The feeders run pipeline.feeder_nice steps nicer than the map,
// and the map's parallel loops run at the map's own priority on every thread, although a niced feeder used
// TBB first: the pipeline starts TBB's workers before its threads.
TEST(Pipeline, FeedersRunNicerThanTheMapAndItsParallelLoops) {
  PipelineOptions options;
  options.feeder_nice = 5;
  std::atomic<int> depth_nice{-100};
  int map_nice = -100;
  std::set<int> loop_nices;
  RecordingSink sink;
  Pipeline pipeline(
      options, std::make_unique<FakeReader>(6),
      [&] { return std::make_unique<NiceRecordingDepth>(&depth_nice); }, std::make_unique<FakeSimplify>(),
      std::make_unique<NiceRecordingMap>(&map_nice, &loop_nices));
  pipeline.AddSink(&sink);
  pipeline.Run();
  ASSERT_EQ(sink.frames.size(), 6u);
  const int caller = ThreadNice();
  EXPECT_EQ(map_nice, caller);
  EXPECT_EQ(depth_nice.load(), std::min(caller + options.feeder_nice, 19));
  EXPECT_EQ(loop_nices, std::set<int>{caller});
}

TEST(Pipeline, ExhaustiveProcessesEveryFrameInOrder) {
  PipelineOptions options;
  options.depth_workers = 3;
  options.queue_capacity = 2;
  RecordingSink sink;
  const auto summary = RunPipeline(options, std::make_unique<FakeReader>(40), &sink);
  ASSERT_EQ(sink.frames.size(), 40u);
  for (int i = 0; i < 40; ++i) EXPECT_EQ(sink.frames[i], i);
  EXPECT_EQ(sink.finishes, 1);
  EXPECT_EQ(sink.triangles, 41u);                     // one per frame + the final flush
  EXPECT_EQ(summary.final_stats.mesh_triangles, 41);  // as published, the final delta included
  EXPECT_EQ(summary.final_stats.frames_processed, 40);
  EXPECT_EQ(summary.final_stats.frames_dropped, 0);
  EXPECT_EQ(summary.frames_read, 40);
  EXPECT_FALSE(summary.stopped_early);
  EXPECT_GT(summary.final_stats.fps, 0.0);
  EXPECT_GT(summary.final_stats.cpu_s, 0.0);
  // Accounting of the last frame (id 39: 49 points, every other kept → 25).
  EXPECT_EQ(sink.last.points_in, 49);
  EXPECT_EQ(sink.last.points_kept, 25);
  ASSERT_EQ(sink.last.stages.size(), 4u);
  EXPECT_EQ(sink.last.stages[1].name, "depth");
  EXPECT_GE(sink.last.stages[1].max_ms, sink.last.stages[1].p50_ms);
}

TEST(Pipeline, FailingFramesAreSkippedAndCounted) {
  PipelineOptions options;
  RecordingSink sink;
  const auto summary =
      RunPipeline(options, std::make_unique<FakeReader>(20, std::set<std::int64_t>{3}), &sink,
                  /*bad_depth=*/{7, 8});
  EXPECT_EQ(summary.final_stats.frames_processed, 17);
  EXPECT_EQ(summary.final_stats.frames_failed, 3);
  ASSERT_EQ(sink.errors.size(), 3u);
  EXPECT_EQ(sink.errors[0].first, 3);
  EXPECT_NE(sink.errors[0].second.find("read: corrupt frame 3"), std::string::npos);
  EXPECT_EQ(sink.errors[1].first, 7);
  EXPECT_NE(sink.errors[1].second.find("depth: no valid disparity"), std::string::npos);
  EXPECT_FALSE(summary.stopped_early);
}

TEST(Pipeline, StopOnErrorEndsTheRunWithoutDeadlock) {
  PipelineOptions options;
  options.on_error = PipelineOptions::OnError::kStop;
  RecordingSink sink;
  const auto summary = RunPipeline(options, std::make_unique<FakeReader>(500), &sink, /*bad_depth=*/{5});
  EXPECT_TRUE(summary.stopped_early);
  EXPECT_NE(summary.fatal_error.find("frame 5"), std::string::npos) << summary.fatal_error;
  EXPECT_LT(summary.final_stats.frames_processed, 500);
  EXPECT_EQ(summary.final_stats.frames_processed + summary.final_stats.frames_failed, summary.frames_read);
  EXPECT_EQ(sink.finishes, 1);  // the mesh so far is still completed
}

// 60 frames 10 ms apart (FakeReader's 0.1 s would make a realtime test take 6 s): the reader paces on them.
class DenseReader : public FakeReader {
 public:
  DenseReader() : FakeReader(60) {}
  std::optional<Frame> Next() override {
    auto f = FakeReader::Next();
    if (f) f->timestamp_s = 0.01 * static_cast<double>(f->id);
    return f;
  }
};

TEST(Pipeline, RealtimeDropsFramesWhenTheMapFallsBehindAndCountsThem) {
  PipelineOptions options;
  options.mode = PipelineOptions::Mode::kRealtime;
  options.queue_capacity = 1;
  RecordingSink sink;
  // A 25 ms map against 10 ms frames must drop.
  const auto summary = RunPipeline(options, std::make_unique<DenseReader>(), &sink, {}, 25ms);
  const auto& s = summary.final_stats;
  EXPECT_GT(s.frames_dropped, 0);
  EXPECT_EQ(s.frames_processed + s.frames_dropped + s.frames_failed, summary.frames_read);
  EXPECT_EQ(summary.frames_read, 60);
  for (size_t i = 1; i < sink.frames.size(); ++i) EXPECT_GT(sink.frames[i], sink.frames[i - 1]);
}

// Frames 0..n-1 but those in `lost`, which it reports through TakeLost() when it passes them (a split run's
// map node does so for frames that never arrived whole); frames sensed `age_s` ago on the Unix clock.
class LossyReader : public FakeReader {
 public:
  LossyReader(int n, std::set<std::int64_t> lost, double age_s = 0.0)
      : FakeReader(n), lost_ids_(std::move(lost)), age_s_(age_s) {}
  std::optional<Frame> Next() override {
    std::optional<Frame> f = FakeReader::Next();
    while (f && lost_ids_.count(f->id)) {
      lost_.push_back({f->id, f->timestamp_s});
      f = FakeReader::Next();
    }
    if (f && age_s_ > 0.0) {
      const double unix_now_s =
          std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
      f->sensed_unix_s = unix_now_s - age_s_;
    }
    return f;
  }
  std::vector<LostFrame> TakeLost() override { return std::exchange(lost_, {}); }

 private:
  std::set<std::int64_t> lost_ids_;
  double age_s_;
  std::vector<LostFrame> lost_;
};

class DropRecordingSink : public RecordingSink {
 public:
  void OnFrame(const FrameStats& stats, const MeshDelta& delta, const std::optional<Pose3d>& pose) override {
    latencies.push_back(stats.latency);
    RecordingSink::OnFrame(stats, delta, pose);
  }
  void OnFrameDropped(std::int64_t frame_id, double timestamp_s, const std::string& reason) override {
    dropped.push_back({frame_id, reason});
    EXPECT_DOUBLE_EQ(timestamp_s, 0.1 * static_cast<double>(frame_id));
  }
  std::vector<std::pair<std::int64_t, std::string>> dropped;
  std::vector<FrameLatency> latencies;
};

TEST(Pipeline, FramesTheReaderLostAreCountedAsDroppedLost) {
  PipelineOptions options;
  DropRecordingSink sink;
  // Frame 19 is the last: reported once the reader has reached the end of the sequence.
  const auto summary =
      RunPipeline(options, std::make_unique<LossyReader>(20, std::set<std::int64_t>{0, 5, 6, 19}), &sink);
  const FrameStats& s = summary.final_stats;
  EXPECT_EQ(s.frames_processed, 16);
  EXPECT_EQ(s.frames_dropped, 4);
  EXPECT_EQ(s.frames_failed, 0);
  const std::vector<std::pair<std::int64_t, std::string>> expected = {
      {0, "lost"}, {5, "lost"}, {6, "lost"}, {19, "lost"}};
  EXPECT_EQ(sink.dropped, expected);
  bool named = false;
  for (const auto& [name, n] : s.dropped_by_reason) {
    if (name == "lost") {
      named = true;
      EXPECT_EQ(n, 4);
    } else {
      EXPECT_EQ(n, 0) << name;
    }
  }
  EXPECT_TRUE(named);
}

// A frame sensed elsewhere 2 s ago is 2 s old when it arrives: its latencies count from its sensing.
TEST(Pipeline, AFrameSensedElsewhereKeepsItsAgeInTheLatencies) {
  PipelineOptions options;
  DropRecordingSink sink;
  const auto summary =
      RunPipeline(options, std::make_unique<LossyReader>(6, std::set<std::int64_t>{}, 2.0), &sink);
  ASSERT_EQ(summary.final_stats.frames_processed, 6);
  ASSERT_EQ(sink.latencies.size(), 6u);
  for (const FrameLatency& l : sink.latencies) {
    EXPECT_GE(l.depth_ms, 2000.0);
    EXPECT_LT(l.depth_ms, 2000.0 + 5000.0);  // the test machine's own delay, generously
    EXPECT_GE(l.published_ms, l.map_ms);
  }
}

TEST(Pipeline, StopRequestDrainsAndFinishes) {
  PipelineOptions options;
  RecordingSink sink;
  Pipeline pipeline(
      options, std::make_unique<FakeReader>(100000), [] { return std::make_unique<FakeDepth>(); },
      std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>(1ms));
  pipeline.AddSink(&sink);
  const auto summary = RunAndStopAfter(pipeline, 100ms);
  EXPECT_TRUE(summary.stopped_early);
  EXPECT_TRUE(summary.fatal_error.empty());
  EXPECT_GT(summary.final_stats.frames_processed, 0);
  EXPECT_LT(summary.final_stats.frames_processed, 100000);
  EXPECT_EQ(summary.final_stats.frames_processed, summary.frames_read);  // everything read was drained
  EXPECT_EQ(sink.finishes, 1);
}

// The map's Finish throws: the error is reported and the final totals stay those of the last frame (not
// the failed finish's empty update).
TEST(Pipeline, AFailingFinishKeepsTheLastFramesTotals) {
  PipelineOptions options;
  RecordingSink sink;
  Pipeline pipeline(
      options, std::make_unique<FakeReader>(5),
      [] { return std::make_unique<FakeDepth>(std::set<std::int64_t>{}); }, std::make_unique<FakeSimplify>(),
      std::make_unique<FakeMap>(0ms, /*finish_throws=*/true));
  pipeline.AddSink(&sink);
  const PipelineSummary summary = pipeline.Run();
  EXPECT_EQ(sink.finishes, 1);
  ASSERT_EQ(sink.errors.size(), 1u);
  EXPECT_NE(sink.errors[0].second.find("final mesh extraction failed"), std::string::npos);
  EXPECT_EQ(summary.final_stats.frames_processed, 5);
  EXPECT_EQ(summary.final_stats.mesh_triangles, 5);  // published by the fifth frame
  EXPECT_GT(summary.final_stats.map_vertices, 0);
}

TEST(Pipeline, AThrowingSinkDoesNotStopTheRun) {
  class BrokenSink : public PipelineSink {
   public:
    void OnFrame(const FrameStats&, const MeshDelta&, const std::optional<Pose3d>&) override {
      throw std::runtime_error("/out/stats.csv: not writable");
    }
    void OnFinish(const FrameStats&, const MeshDelta&) override {
      throw std::runtime_error("/out/mesh.ply: disk full");
    }
  };
  PipelineOptions options;
  RecordingSink good;
  BrokenSink broken;
  Pipeline pipeline(
      options, std::make_unique<FakeReader>(10), [] { return std::make_unique<FakeDepth>(); },
      std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>());
  pipeline.AddSink(&broken);
  pipeline.AddSink(&good);
  const auto summary = pipeline.Run();
  EXPECT_EQ(good.frames.size(), 10u);
  EXPECT_EQ(good.finishes, 1);
  EXPECT_EQ(summary.sink_errors, 11);
  EXPECT_NE(summary.first_sink_error.find("/out/stats.csv"), std::string::npos);
}

// Frames 0.1 s apart whose camera moves 1 m per frame along x, except where `poses` says otherwise.
class PoseReader : public FrameReader {
 public:
  PoseReader(int n, std::map<std::int64_t, Pose3d> poses) : n_(n), poses_(std::move(poses)) {}
  std::optional<Frame> Next() override {
    if (next_ >= n_) return std::nullopt;
    Frame f;
    f.id = next_++;
    f.timestamp_s = 0.1 * static_cast<double>(f.id);
    f.world_from_cam = Pose3d(Eigen::Translation3d(static_cast<double>(f.id), 0, 0));
    if (auto it = poses_.find(f.id); it != poses_.end()) f.world_from_cam = it->second;
    return f;
  }

 private:
  int n_;
  std::int64_t next_ = 0;
  std::map<std::int64_t, Pose3d> poses_;
};

TEST(Pipeline, NonFiniteNonRigidAndJumpingPosesAreSkippedAndCounted) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Pose3d sheared = Pose3d(Eigen::Translation3d(4, 0, 0));
  sheared.matrix()(0, 1) = 0.5;
  const std::map<std::int64_t, Pose3d> poses = {
      {2, Pose3d(Eigen::Translation3d(nan, 0, 0))},
      {4, sheared},
      {6, Pose3d(Eigen::Translation3d(1000, 0, 0))},  // 1 km in 0.1 s: a GPS jump
  };
  RecordingSink sink;
  const auto summary = RunPipeline({}, std::make_unique<PoseReader>(10, poses), &sink);
  EXPECT_EQ(sink.frames, (std::vector<std::int64_t>{0, 1, 3, 5, 7, 8, 9}));
  EXPECT_EQ(summary.final_stats.frames_failed, 3);
  ASSERT_EQ(sink.errors.size(), 3u);
  EXPECT_EQ(sink.errors[0].first, 2);
  EXPECT_NE(sink.errors[0].second.find("pose: frame 2: pose is not finite"), std::string::npos)
      << sink.errors[0].second;
  EXPECT_NE(sink.errors[1].second.find("not a rotation"), std::string::npos) << sink.errors[1].second;
  EXPECT_EQ(sink.errors[2].first, 6);
  // Frame 7 is compared with frame 5, the last accepted one (2 m in 0.2 s).
  EXPECT_NE(sink.errors[2].second.find("pose jumps 995.0 m in 0.10 s since frame 5"), std::string::npos)
      << sink.errors[2].second;
  EXPECT_FALSE(summary.stopped_early);
}

TEST(Pipeline, SpeedCheckCanBeTurnedOffAndAPermanentJumpEndsTheRun) {
  // From frame 3 on the track is 5 km away for good.
  std::map<std::int64_t, Pose3d> poses;
  for (int i = 3; i < 400; ++i) poses[i] = Pose3d(Eigen::Translation3d(5000.0 + i, 0, 0));
  {
    PipelineOptions options;
    options.max_speed_mps = 0.0;
    RecordingSink sink;
    const auto summary = RunPipeline(options, std::make_unique<PoseReader>(400, poses), &sink);
    EXPECT_EQ(summary.final_stats.frames_processed, 400);
  }
  RecordingSink sink;
  const auto summary = RunPipeline({}, std::make_unique<PoseReader>(400, poses), &sink);
  EXPECT_TRUE(summary.stopped_early);
  EXPECT_NE(summary.fatal_error.find("100 frames in a row"), std::string::npos) << summary.fatal_error;
  EXPECT_EQ(summary.final_stats.frames_processed, 3);
  EXPECT_EQ(summary.final_stats.frames_processed + summary.final_stats.frames_failed, summary.frames_read);
  EXPECT_EQ(sink.finishes, 1);
}

// Records OpenCV's thread count as the depth stage sees it.
class OpenCvThreadsRecordingDepth : public FakeDepth {
 public:
  explicit OpenCvThreadsRecordingDepth(std::atomic<int>* threads) : threads_(threads) {}
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* labels) override {
    threads_->store(cv::getNumThreads());
    return FakeDepth::Process(frame, labels);
  }

 private:
  std::atomic<int>* threads_;
};

// pipeline.opencv_threads holds during the run (SGBM runs on the calling depth thread) and OpenCV's own
// setting comes back after it; 0 leaves OpenCV's setting alone.
TEST(Pipeline, OpenCvThreadsHoldDuringTheRunAndAreRestoredAfter) {
  const int before = cv::getNumThreads();
  for (const int threads : {1, 0}) {
    PipelineOptions options;
    options.opencv_threads = threads;
    std::atomic<int> seen{-100};
    RecordingSink sink;
    Pipeline pipeline(
        options, std::make_unique<FakeReader>(3),
        [&] { return std::make_unique<OpenCvThreadsRecordingDepth>(&seen); },
        std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>());
    pipeline.AddSink(&sink);
    pipeline.Run();
    ASSERT_EQ(sink.frames.size(), 3u);
    EXPECT_EQ(seen.load(), threads == 0 ? before : threads) << "opencv_threads " << threads;
    EXPECT_EQ(cv::getNumThreads(), before) << "opencv_threads " << threads;
  }
}

TEST(PipelineOptions, CheckNamesTheField) {
  PipelineOptions o;
  o.depth_workers = 0;
  try {
    o.Check();
    FAIL();
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "depth_workers");
  }
}

TEST(PipelineOptions, NegativeOpenCvThreadsAreRejected) {
  PipelineOptions o;
  o.opencv_threads = -1;
  try {
    o.Check();
    FAIL();
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "opencv_threads");
  }
}

TEST(Pipeline, RssAndCpuTimeAreMeasured) {
  EXPECT_GT(CurrentRssMb(), 1.0);
  const double before = ProcessCpuSeconds();
  volatile double x = 0.0;
  for (int i = 0; i < 20000000; ++i) x = x + 1.0;
  EXPECT_GT(ProcessCpuSeconds(), before);
}

// ---- Keyframe segmentation on its own thread (Pipeline::SetSegmentStage) ----

// Labels every keyframe with its own id (a 1×1 label image); records the keyframes in the order it got them
// and the threads it ran on; optionally slow, and failing on some ids.
class FakeSegment : public SegmentStage {
 public:
  struct Log {
    std::mutex mutex;
    std::vector<std::int64_t> keyframes;
    std::set<std::thread::id> threads;
  };
  FakeSegment(Log* log, std::chrono::milliseconds delay = 0ms, std::set<std::int64_t> bad = {})
      : log_(log), delay_(delay), bad_(std::move(bad)) {}
  cv::Mat Process(const Frame& keyframe) override {
    std::this_thread::sleep_for(delay_);
    {
      std::lock_guard<std::mutex> lock(log_->mutex);
      log_->keyframes.push_back(keyframe.id);
      log_->threads.insert(std::this_thread::get_id());
    }
    if (bad_.count(keyframe.id)) throw std::runtime_error("network failed");
    return cv::Mat(1, 1, CV_8UC1, cv::Scalar(static_cast<int>(keyframe.id)));
  }

 private:
  Log* log_;
  std::chrono::milliseconds delay_;
  std::set<std::int64_t> bad_;
};

// FakeDepth that records, per frame, the keyframe whose labels it received (-1: none), checking that the
// label image is that keyframe's.
class KeyframeRecordingDepth : public FakeDepth {
 public:
  struct Log {
    std::mutex mutex;
    std::map<std::int64_t, std::int64_t> keyframe_of;
  };
  explicit KeyframeRecordingDepth(Log* log) : log_(log) {}
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* keyframe) override {
    std::int64_t id = -1;
    if (keyframe != nullptr) {
      id = keyframe->frame_id;
      EXPECT_EQ(keyframe->labels.at<std::uint8_t>(0, 0), id) << "frame " << frame.id;
      EXPECT_TRUE(keyframe->world_from_cam.has_value());
    }
    {
      std::lock_guard<std::mutex> lock(log_->mutex);
      log_->keyframe_of[frame.id] = id;
    }
    return FakeDepth::Process(frame, keyframe);
  }

 private:
  Log* log_;
};

struct KeyframeRun {
  PipelineSummary summary;
  RecordingSink sink;
  FakeSegment::Log segment_log;
  KeyframeRecordingDepth::Log depth_log;
};

void RunWithKeyframes(KeyframeRun* run, int every_frames, std::unique_ptr<FrameReader> reader,
                      std::chrono::milliseconds segment_delay = 0ms,
                      std::set<std::int64_t> bad_keyframes = {}, PipelineOptions options = {}) {
  Pipeline pipeline(
      options, std::move(reader), [run] { return std::make_unique<KeyframeRecordingDepth>(&run->depth_log); },
      std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>());
  pipeline.SetSegmentStage(std::make_unique<FakeSegment>(&run->segment_log, segment_delay, bad_keyframes),
                           every_frames);
  pipeline.AddSink(&run->sink);
  run->summary = pipeline.Run();
}

TEST(PipelineKeyframes, SegmentsEveryNthFrameAndGivesEachFrameItsKeyframe) {
  KeyframeRun run;
  PipelineOptions options;
  options.depth_workers = 3;
  RunWithKeyframes(&run, 3, std::make_unique<FakeReader>(11), 0ms, {}, options);
  EXPECT_EQ(run.segment_log.keyframes, (std::vector<std::int64_t>{0, 3, 6, 9}));
  EXPECT_EQ(run.segment_log.threads.size(), 1u);  // one segment thread
  EXPECT_EQ(run.segment_log.threads.count(std::this_thread::get_id()), 0u);
  ASSERT_EQ(run.depth_log.keyframe_of.size(), 11u);
  for (std::int64_t k = 0; k < 11; ++k) EXPECT_EQ(run.depth_log.keyframe_of[k], k / 3 * 3) << "frame " << k;
  EXPECT_EQ(run.summary.final_stats.frames_processed, 11);
  // Reported: the segment stage after read, its time only on keyframes; the depth worker's wait.
  const auto& stages = run.sink.last.stages;
  ASSERT_GE(stages.size(), 6u);
  EXPECT_EQ(stages[0].name, "read");
  EXPECT_EQ(stages[1].name, "segment");
  EXPECT_EQ(stages[2].name, "depth");
  bool wait_reported = false;
  for (const auto& s : stages) wait_reported |= s.name == "depth.label_wait";
  EXPECT_TRUE(wait_reported);
}

// The same keyframes and the same labels per frame whatever the segmenter's speed: nothing depends on timing.
TEST(PipelineKeyframes, ASlowSegmenterChangesNothingButTime) {
  KeyframeRun fast, slow;
  RunWithKeyframes(&fast, 4, std::make_unique<FakeReader>(13));
  RunWithKeyframes(&slow, 4, std::make_unique<FakeReader>(13), 15ms);
  EXPECT_EQ(slow.segment_log.keyframes, fast.segment_log.keyframes);
  EXPECT_EQ(slow.depth_log.keyframe_of, fast.depth_log.keyframe_of);
  EXPECT_EQ(slow.sink.frames, fast.sink.frames);
  EXPECT_EQ(slow.summary.final_stats.frames_processed, 13);
}

// A frame that cannot be read is no keyframe: the next one read is, when due.
TEST(PipelineKeyframes, AnUnreadableKeyframeMovesTheKeyframeToTheNextFrame) {
  KeyframeRun run;
  RunWithKeyframes(&run, 3, std::make_unique<FakeReader>(8, std::set<std::int64_t>{3}));
  EXPECT_EQ(run.segment_log.keyframes, (std::vector<std::int64_t>{0, 4, 7}));
  EXPECT_EQ(run.depth_log.keyframe_of[5], 4);
  EXPECT_EQ(run.summary.final_stats.frames_failed, 1);
}

// The segmenter fails on keyframe 3: frames 3, 4, 5 fail (stage "segment", naming the keyframe), the others
// map.
TEST(PipelineKeyframes, ASegmenterErrorFailsTheFramesOfThatKeyframe) {
  KeyframeRun run;
  RunWithKeyframes(&run, 3, std::make_unique<FakeReader>(9), 0ms, {3});
  EXPECT_EQ(run.summary.final_stats.frames_processed, 6);
  EXPECT_EQ(run.summary.final_stats.frames_failed, 3);
  ASSERT_EQ(run.sink.errors.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(run.sink.errors[i].first, static_cast<std::int64_t>(3 + i));
    EXPECT_EQ(run.sink.errors[i].second, "segment: keyframe 3: network failed");
  }
  EXPECT_EQ(run.sink.frames, (std::vector<std::int64_t>{0, 1, 2, 6, 7, 8}));
}

// A stop request (SIGINT / SIGTERM) while the segmenter is busy: every frame read is drained with its
// keyframe's labels, the mesh is finished, nothing hangs.
TEST(PipelineKeyframes, StopRequestDrainsWithTheSegmentThread) {
  KeyframeRun run;
  Pipeline pipeline(
      PipelineOptions{}, std::make_unique<FakeReader>(100000),
      [&run] { return std::make_unique<KeyframeRecordingDepth>(&run.depth_log); },
      std::make_unique<FakeSimplify>(), std::make_unique<FakeMap>());
  pipeline.SetSegmentStage(std::make_unique<FakeSegment>(&run.segment_log, 5ms), 2);
  pipeline.AddSink(&run.sink);
  const auto summary = RunAndStopAfter(pipeline, 100ms);
  EXPECT_TRUE(summary.stopped_early);
  EXPECT_GT(summary.final_stats.frames_processed, 0);
  EXPECT_EQ(summary.final_stats.frames_processed, summary.frames_read);
  EXPECT_EQ(summary.final_stats.frames_failed, 0);
  EXPECT_EQ(run.sink.finishes, 1);
  for (const auto& [frame, keyframe] : run.depth_log.keyframe_of) EXPECT_EQ(keyframe, frame / 2 * 2);
}

// Realtime: a segmenter slower than the frames never blocks the reader; a keyframe that finds the segment
// queue full is not taken (a later frame is), frames go on with the last keyframe taken, and everything read
// is processed, dropped or failed, counted.
TEST(PipelineKeyframes, RealtimeWithASlowSegmenterNeverBlocksTheReader) {
  KeyframeRun run;
  PipelineOptions options;
  options.mode = PipelineOptions::Mode::kRealtime;
  options.queue_capacity = 1;
  RunWithKeyframes(&run, 2, std::make_unique<DenseReader>(), 30ms, {}, options);
  const auto& s = run.summary.final_stats;
  EXPECT_EQ(run.summary.frames_read, 60);
  EXPECT_EQ(s.frames_processed + s.frames_dropped + s.frames_failed, 60);
  EXPECT_EQ(s.frames_failed, 0);
  EXPECT_GT(s.frames_processed, 0);
  const auto& keyframes = run.segment_log.keyframes;
  ASSERT_FALSE(keyframes.empty());
  EXPECT_LE(keyframes.size(), 30u);  // at most every other frame, fewer when the queue was full
  for (std::size_t i = 1; i < keyframes.size(); ++i) EXPECT_GE(keyframes[i] - keyframes[i - 1], 2);
  for (const auto& [frame, keyframe] : run.depth_log.keyframe_of) {
    EXPECT_LE(keyframe, frame);
    EXPECT_TRUE(std::find(keyframes.begin(), keyframes.end(), keyframe) != keyframes.end()) << frame;
  }
}

// Without a segment stage the depth stage gets no keyframe labels.
TEST(PipelineKeyframes, NoSegmentStageNoKeyframeLabels) {
  KeyframeRecordingDepth::Log log;
  RecordingSink sink;
  Pipeline pipeline(
      PipelineOptions{}, std::make_unique<FakeReader>(5),
      [&log] { return std::make_unique<KeyframeRecordingDepth>(&log); }, std::make_unique<FakeSimplify>(),
      std::make_unique<FakeMap>());
  pipeline.AddSink(&sink);
  pipeline.Run();
  ASSERT_EQ(log.keyframe_of.size(), 5u);
  for (const auto& [frame, keyframe] : log.keyframe_of) EXPECT_EQ(keyframe, -1);
  EXPECT_EQ(sink.last.stages.size(), 4u);
}

}  // namespace
}  // namespace semap
