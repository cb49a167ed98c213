// The narrow interfaces the streaming pipeline connects. Each stage is a plain object with one Process()
// call, testable alone without threads; the Pipeline owns the threads, the queues and the accounting.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/frame.h"
#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh_delta.h"
#include "engine/pipeline/frame_stats.h"
#include "engine/semantics/keyframe_labels.h"

namespace semap {

// Where frames come from (io/ adapts its FrameSource to it). Called from one thread.
class FrameReader {
 public:
  virtual ~FrameReader() = default;
  // The next frame, or std::nullopt at the end of the sequence. A frame that cannot be read throws (any
  // std::exception): the pipeline reports it, counts it as failed and asks for the next one.
  virtual std::optional<Frame> Next() = 0;

  // A frame of the sequence that the reader will never return (a split run's map node: its parts did not all
  // arrive in time).
  struct LostFrame {
    std::int64_t frame_id = -1;
    double timestamp_s = 0.0;
  };
  // The frames lost since the last call, oldest first; the pipeline counts each as dropped, reason "lost".
  // Called after each Next() and once at the end of the sequence.
  virtual std::vector<LostFrame> TakeLost() { return {}; }
};

// Stereo depth + semantic labelling of one frame: the frame's labelled points in the world frame, with the
// frame's camera as camera 0. One instance per depth worker thread (see DepthStageFactory).
class DepthStage {
 public:
  virtual ~DepthStage() = default;
  // `keyframe_labels`: when the pipeline has a segment stage, the segmentation of this frame's keyframe (the
  // frame itself, or the nearest earlier keyframe), to label the frame from; nullptr otherwise (the stage
  // labels the frame by itself).
  virtual LabelledCloud Process(const Frame& frame, const KeyframeLabels* keyframe_labels) = 0;
  // Realtime mode, once, before the first frame is due: whatever would make the first frames late (a
  // network's first forward pass), done on the sequence's first frame. Its result is not used.
  virtual void Prepare(const Frame& first_frame) {}
};

// Where a split run's depth node hands each frame's depth and labels (a publisher to the map node). Called
// from the depth workers, several at once, in any frame order: implementations are thread-safe.
class FrameDepthSink {
 public:
  virtual ~FrameDepthSink() = default;
  virtual void OnFrameDepth(const Frame& frame, const FrameDepth& depth) = 0;
};

// Per-pixel labels of keyframes (a slow segmenter, ENet), on the pipeline's own segment thread, concurrently
// with the depth workers: called once per keyframe, in frame order, from that one thread.
class SegmentStage {
 public:
  virtual ~SegmentStage() = default;
  // The label image of `keyframe`'s left image (CV_8UC1, ClassMap ids, the image's size). Throws (any
  // std::exception) when it cannot: the frames that take their labels from this keyframe fail.
  virtual cv::Mat Process(const Frame& keyframe) = 0;
  // As DepthStage::Prepare.
  virtual void Prepare(const Frame& first_frame) {}
};

// Windowed simplification: called once per frame, in frame order, from one thread.
class SimplifyStage {
 public:
  virtual ~SimplifyStage() = default;
  // The kept points of `cloud`; `counts` receives per-class in/kept counts for this frame.
  virtual LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) = 0;
};

// The time of one step inside a stage (reported as stage "<stage>.<name>", e.g. "map.votes").
struct StepTime {
  std::string name;
  double ms = 0.0;
};

// The map's surface as its stage extracted it; MeshPublisher turns it into a delta.
struct MeshSnapshot {
  IdentifiedMesh live;       // the whole live surface
  IdentifiedMesh finalised;  // the regions finalised since the last snapshot: published once, never removed
};

// What the map reports after each update.
struct MapUpdate {
  std::int64_t frame_id = -1;        // the frame of the update (Finish(): the last frame)
  std::optional<MeshSnapshot> mesh;  // when the stage extracted its surface this time (its mesh cadence)
  std::int64_t vertices = 0;
  std::int64_t cells = 0;
  std::int64_t rays = 0;
  // Where the map stage's time went, the same steps in the same order every frame.
  std::vector<StepTime> steps;
};

// Turns a map stage's updates into the deltas its subscribers receive (the pipeline's output thread does, off
// the map's critical path), counting the triangles published so far. Not thread-safe.
class MeshPublisher {
 public:
  // The delta that publishes `update`: its snapshot diffed against what went out before, or an empty delta
  // of its frame when it has none.
  MeshDelta Publish(const MapUpdate& update) {
    MeshDelta delta;
    delta.frame_id = update.frame_id;
    if (!update.mesh) return delta;
    delta = differ_.Update(update.frame_id, update.mesh->live, update.mesh->finalised);
    published_triangles_ += static_cast<std::int64_t>(delta.added_triangle_ids.size()) -
                            static_cast<std::int64_t>(delta.removed_triangle_ids.size());
    return delta;
  }
  std::int64_t published_triangles() const { return published_triangles_; }

 private:
  MeshDiffer differ_;  // live surface + finalised regions → deltas with stable triangle ids
  std::int64_t published_triangles_ = 0;
};

// The incremental map: called once per frame, in frame order, from one thread.
class MapStage {
 public:
  virtual ~MapStage() = default;
  virtual MapUpdate Process(const LabelledCloud& cloud, const Pose3d& world_from_cam) = 0;
  // End of the sequence: finalise everything; the returned delta completes the mesh.
  virtual MapUpdate Finish() = 0;
};

// Receives the pipeline's output, from the pipeline's output thread (one call at a time).
class PipelineSink {
 public:
  virtual ~PipelineSink() = default;
  virtual void OnFrame(const FrameStats& stats, const MeshDelta& delta,
                       const std::optional<Pose3d>& world_from_cam) = 0;
  // A frame that failed in `stage` (read, depth, simplify, map) and was skipped or stopped the run.
  virtual void OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) {}
  // A frame never integrated because the engine was behind (realtime mode), or lost on its way from another
  // host: `reason` is one of FrameStats::dropped_by_reason's names.
  virtual void OnFrameDropped(std::int64_t frame_id, double timestamp_s, const std::string& reason) {}
  // The end of the run: `final_delta` completes the mesh; `stats` is the final accounting.
  virtual void OnFinish(const FrameStats& stats, const MeshDelta& final_delta) {}
};

}  // namespace semap
