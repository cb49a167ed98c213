// semap's concrete pipeline stages: thin adapters from the stage interfaces (stages.h) to the depth,
// semantics, simplification and map modules.
#pragma once

#include <memory>
#include <optional>

#include "engine/core/class_map.h"
#include "engine/depth/plane_sweep.h"
#include "engine/depth/stereo_depth.h"
#include "engine/depth/stereo_sweep.h"
#include "engine/map/incremental_map.h"
#include "engine/pipeline/stages.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "engine/simplify/windowed_simplifier.h"

namespace semap {

// SGBM depth (a frame without a right image: plane-sweep depth against its neighbour views, as
// SweepFrameDisparity gives it), then the paper's labelling rule: the frame's points are labelled from the
// frame's own label image (its camera is their first camera); points labelled sky are dropped
// (semantics.drop_sky). A frame that gives no point at all (no valid disparity, or only sky) throws: the
// pipeline skips and counts it. Measures the rig's residual row misalignment (FitRowOffsets,
// depth.align_rows) on the frames it reads and hands each frame the last measurement (Frame::row_offsets), so
// that the depth workers only resample the right image instead of each measuring its own pair (~30 ms a
// frame). Every frame is measured until one fits, for the first kFirstAttemptFrames frames; after that, and
// after a fit, every kRemeasureEveryFrames frames, each fit replacing the one before (a rig's rectification
// holds for a drive; a new measurement follows a change of camera). A frame read before any fit carries
// "measured, nothing to correct". Frames are passed on in order, so every run of the same frames gets the
// same offsets. Runs on the reader's thread; one thread calls Next().
class RowAlignmentReader : public FrameReader {
 public:
  static constexpr int kFirstAttemptFrames = 10;
  static constexpr int kRemeasureEveryFrames = 100;

  explicit RowAlignmentReader(std::unique_ptr<FrameReader> source);
  std::optional<Frame> Next() override;

 private:
  std::unique_ptr<FrameReader> source_;
  std::optional<RowOffsets> current_;
  int frames_read_ = 0;
  int frames_since_attempt_ = 0;
};

// Gives each stereo frame with a pose its right view and the left views of the plane_sweep.stereo_past_frames
// frames before it (PastFrameViews), for the depth stage to sweep beside SGBM. Runs on the reader's thread
// after the readers that set the poses; one thread calls Next().
class StereoNeighbourReader : public FrameReader {
 public:
  StereoNeighbourReader(std::unique_ptr<FrameReader> source, int past_frames);
  std::optional<Frame> Next() override;
  std::vector<LostFrame> TakeLost() override { return source_->TakeLost(); }

 private:
  std::unique_ptr<FrameReader> source_;
  PastFrameViews views_;
};

// The frame's label image is, given keyframe labels (a pipeline with a SegmenterStage), the keyframe's own
// on a keyframe, else the keyframe's carried over as semantics.enet_propagation says (reprojected through
// this frame's SGBM depth and the relative pose, or reused); without, FrameLabels() (the frame's label image,
// or ENet run here when semantics.source is enet). One instance per depth worker (owns its segmenter, which
// is loaded only when `labels_from_keyframes` is false and the source is enet).
class StereoLabelStage : public DepthStage {
 public:
  StereoLabelStage(const DepthOptions& depth, const SemanticsOptions& semantics, ClassMap class_map,
                   bool labels_from_keyframes = false, const PlaneSweepOptions& sweep = {});
  // ToCloud(frame, *frame.depth) when the frame carries its depth, else ToCloud(frame, ComputeDepth(...)).
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* keyframe_labels) override;
  // With its own segmenter: runs it once on the first frame (its first forward pass sets the network up).
  void Prepare(const Frame& first_frame) override;

  // The frame's disparity, confidence and label image (the first half of Process).
  FrameDepth ComputeDepth(const Frame& frame, const KeyframeLabels* keyframe_labels);
  // The frame's labelled cloud from its depth (the second half of Process): the same cloud wherever `depth`
  // was computed. Throws std::runtime_error naming the frame when it gives no point (no valid disparity, or
  // only sky).
  LabelledCloud ToCloud(const Frame& frame, const FrameDepth& depth) const;

 private:
  // The frame's disparity (and confidence): SGBM on its pair (with the sweep beside it when the frame has
  // earlier frames' views: StereoSweepDisparity), or the plane sweep without one.
  DisparityResult Disparity(const Frame& frame) const;

  StereoDepth depth_;
  PlaneSweepDepth sweep_;
  PlaneSweepDepth stereo_sweep_;  // StereoFrameSweepOptions(sweep)
  SemanticsOptions semantics_;
  ClassMap class_map_;
  std::optional<Label> sky_label_;        // points of this label are dropped when semantics.drop_sky
  std::unique_ptr<Segmenter> segmenter_;  // only for the ENet source, without keyframe labels
};

// A split run's depth node: each frame's depth and labels (StereoLabelStage::ComputeDepth) go to `sink`, and
// the frame's cloud is left empty (its camera_frame_ids name the frame): the map is another process's. One
// instance per depth worker; the sink is shared by them (not owned; must outlive the pipeline).
class FrameDepthStage : public DepthStage {
 public:
  FrameDepthStage(std::unique_ptr<StereoLabelStage> stage, FrameDepthSink* sink);
  LabelledCloud Process(const Frame& frame, const KeyframeLabels* keyframe_labels) override;
  void Prepare(const Frame& first_frame) override { stage_->Prepare(first_frame); }

 private:
  std::unique_ptr<StereoLabelStage> stage_;
  FrameDepthSink* sink_;
};

// A depth node's simplification: the cloud as it is (empty: FrameDepthStage's).
class PassThroughSimplifyStage : public SimplifyStage {
 public:
  LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>*) override { return cloud; }
};

// A depth node's map: none; each update names its frame and carries no mesh.
class NoMapStage : public MapStage {
 public:
  MapUpdate Process(const LabelledCloud& cloud, const Pose3d& world_from_cam) override;
  MapUpdate Finish() override;

 private:
  std::int64_t last_frame_id_ = -1;
};

// The segment stage of a pipeline whose labels come from a segmenter (semantics.source enet): the keyframe's
// left image through the segmenter (loaded at construction: a missing model is an error before any frame).
class SegmenterStage : public SegmentStage {
 public:
  explicit SegmenterStage(const SemanticsOptions& semantics);
  cv::Mat Process(const Frame& keyframe) override;
  // Runs the segmenter once on the first frame (its first forward pass sets the network up).
  void Prepare(const Frame& first_frame) override;

 private:
  std::unique_ptr<Segmenter> segmenter_;
};

// The windowed simplifier (any method by name, O = keep everything).
class WindowedSimplifyStage : public SimplifyStage {
 public:
  WindowedSimplifyStage(const SimplifyOptions& options, ClassMap class_map);
  LabelledCloud Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) override;

 private:
  WindowedSimplifier simplifier_;
};

// The incremental Delaunay map: each frame's kept points with their camera update the map, and every
// `mesh_every_frames` frames of the sequence (PipelineOptions::mesh_every_frames: frame ids, so frames not
// integrated count too) and at the end its surface goes out as a snapshot (live surface + regions finalised
// since the last one); the frames between give none.
class IncrementalMapStage : public MapStage {
 public:
  // mesh_every_frames: PipelineOptions::mesh_every_frames (≥ 1).
  IncrementalMapStage(const MapOptions& options, int mesh_every_frames);
  MapUpdate Process(const LabelledCloud& cloud, const Pose3d& world_from_cam) override;
  MapUpdate Finish() override;
  // The map's sizes and work counters so far (a pass over every cell: for reports, not every frame).
  MapStatistics Statistics() const { return map_.Statistics(); }

 private:
  // The map's sizes, with its surface when `with_mesh`.
  MapUpdate Report(bool with_mesh);
  IncrementalMap map_;
  int mesh_every_frames_;
  std::optional<std::int64_t> next_mesh_frame_id_;  // the first frame id whose update extracts the surface
  std::int64_t last_frame_id_ = -1;
};

}  // namespace semap
