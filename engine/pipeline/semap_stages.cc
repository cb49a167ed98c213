#include "engine/pipeline/semap_stages.h"

#include <stdexcept>
#include <string>

#include "engine/core/check.h"
#include "engine/core/stopwatch.h"
#include "engine/depth/dominant_planes.h"
#include "engine/depth/frame_sweep.h"
#include "engine/depth/row_alignment.h"

namespace semap {

StereoLabelStage::StereoLabelStage(const DepthOptions& depth, const SemanticsOptions& semantics,
                                   ClassMap class_map, bool labels_from_keyframes,
                                   const PlaneSweepOptions& sweep)
    : depth_(depth),
      sweep_(sweep),
      stereo_sweep_(StereoFrameSweepOptions(sweep)),
      semantics_(semantics),
      class_map_(std::move(class_map)),
      sky_label_(SkyLabel(class_map_)),
      segmenter_(labels_from_keyframes ? nullptr : MakeSegmenter(semantics)) {}

void StereoLabelStage::Prepare(const Frame& first_frame) {
  if (segmenter_ && !first_frame.left.empty()) segmenter_->Segment(first_frame.left);
}

SegmenterStage::SegmenterStage(const SemanticsOptions& semantics) : segmenter_(MakeSegmenter(semantics)) {
  SEMAP_ASSERT(segmenter_ != nullptr,
               "semantics.source " << LabelSourceName(semantics.source) << " has no segmenter");
}

cv::Mat SegmenterStage::Process(const Frame& keyframe) { return segmenter_->Segment(keyframe.left); }

void SegmenterStage::Prepare(const Frame& first_frame) {
  if (!first_frame.left.empty()) segmenter_->Segment(first_frame.left);
}

namespace {

// Marks the view's pixels labelled `sky` as free up to the far range: no point, but their rays carve.
void MarkSky(const cv::Mat& labels, Label sky, int stride_px, DepthView* view) {
  for (int j = 0; j < view->depth_m.rows; ++j) {
    float* row = view->depth_m.ptr<float>(j);
    const std::uint8_t* l = labels.ptr<std::uint8_t>(j * stride_px);
    for (int i = 0; i < view->depth_m.cols; ++i) {
      if (l[i * stride_px] == sky) row[i] = kFreeToFarRange;
    }
  }
}

// The label image of `frame` from its keyframe's: the keyframe's own, or carried over
// (semantics.enet_propagation); reused when a pose is missing or the sizes differ (nothing to reproject
// with).
cv::Mat LabelsFromKeyframe(const Frame& frame, const KeyframeLabels& keyframe, const cv::Mat& disparity_px,
                           const SemanticsOptions& semantics, Label unlabelled_id) {
  if (keyframe.frame_id == frame.id || semantics.enet_propagation == LabelPropagation::kReuse ||
      !keyframe.world_from_cam || !frame.world_from_cam || keyframe.labels.type() != CV_8UC1 ||
      keyframe.labels.size() != frame.left.size() || disparity_px.size() != frame.left.size()) {
    return keyframe.labels;
  }
  StereoCalibration intrinsics = frame.calibration;
  intrinsics.width_px = frame.left.cols;
  intrinsics.height_px = frame.left.rows;
  return PropagateLabels(keyframe, *frame.world_from_cam, DepthMapFromDisparity(disparity_px, intrinsics),
                         intrinsics, unlabelled_id);
}

}  // namespace

RowAlignmentReader::RowAlignmentReader(std::unique_ptr<FrameReader> source) : source_(std::move(source)) {}

std::optional<Frame> RowAlignmentReader::Next() {
  std::optional<Frame> frame = source_->Next();
  if (!frame) return frame;
  ++frames_since_attempt_;  // this frame included: an attempt at frame a, the next at frame a + 100
  const bool due =
      frames_since_attempt_ >= kRemeasureEveryFrames || (!current_ && frames_read_ < kFirstAttemptFrames);
  ++frames_read_;
  const int type = frame->left.type();
  if (due && !frame->left.empty() && frame->left.size() == frame->right.size() &&
      type == frame->right.type() && (type == CV_8UC1 || type == CV_8UC3)) {
    frames_since_attempt_ = 0;
    if (std::optional<RowOffsets> fit = FitRowOffsets(frame->left, frame->right)) current_ = *fit;
  }
  if (current_) {
    frame->row_offsets = current_;
  } else {
    RowOffsets none;  // measured, nothing to correct: the depth stage does not measure again
    none.image_size = frame->left.size();
    frame->row_offsets = none;
  }
  return frame;
}

StereoNeighbourReader::StereoNeighbourReader(std::unique_ptr<FrameReader> source, int past_frames)
    : source_(std::move(source)), views_(past_frames) {}

std::optional<Frame> StereoNeighbourReader::Next() {
  std::optional<Frame> frame = source_->Next();
  if (frame) views_.Attach(&*frame);
  return frame;
}

DisparityResult StereoLabelStage::Disparity(const Frame& frame) const {
  if (frame.right.empty()) return SweepFrameDisparity(frame, sweep_, depth_.options().half_resolution);
  return StereoSweepDisparity(frame, depth_, stereo_sweep_);
}

FrameDepth StereoLabelStage::ComputeDepth(const Frame& frame, const KeyframeLabels* keyframe_labels) {
  DisparityResult disparity = Disparity(frame);
  cv::Mat labels = keyframe_labels != nullptr
                       ? LabelsFromKeyframe(frame, *keyframe_labels, disparity.disparity_px, semantics_,
                                            class_map_.unlabelled_id())
                       : FrameLabels(frame, semantics_, segmenter_.get());
  if (frame.right.empty() && sweep_.options().label_directions) {
    // The ground's and the walls' planes from the first sweep's depth and the labels, swept as well.
    const std::vector<SweepDirection> directions =
        DominantDirections(DepthMapFromDisparity(disparity.disparity_px, frame.calibration), labels,
                           FrameCamera(frame), class_map_);
    if (!directions.empty()) {
      disparity = SweepFrameDisparity(frame, sweep_, depth_.options().half_resolution, directions);
    }
  }
  return FrameDepth{std::move(disparity.disparity_px), std::move(disparity.confidence), std::move(labels)};
}

LabelledCloud StereoLabelStage::ToCloud(const Frame& frame, const FrameDepth& depth) const {
  LabelledCloud cloud = depth_.ToCloud(frame, depth.disparity_px, depth.confidence);
  DepthView view = depth_.ToDepthView(frame, depth.disparity_px, depth.confidence);
  if (cloud.size() == 0) {
    // Nothing to map (uniform, black or unmatched images): the frame is skipped and counted, not mapped
    // empty.
    throw std::runtime_error("frame " + std::to_string(frame.id) +
                             ": no valid disparity (no point in the depth "
                             "range; uniform, dark or unmatched images?)");
  }
  const cv::Mat& labels = depth.labels;
  ApplyFirstCameraLabels(cloud, frame.id, labels, frame.left.size(), class_map_.unlabelled_id(),
                         semantics_.size_mismatch);
  if (semantics_.drop_sky && sky_label_ && RemoveLabel(cloud, *sky_label_) > 0 && cloud.size() == 0) {
    throw std::runtime_error("frame " + std::to_string(frame.id) +
                             ": every point is sky (semantics.drop_sky)");
  }
  if (semantics_.drop_sky && sky_label_ && labels.size() == frame.left.size() && labels.type() == CV_8UC1) {
    MarkSky(labels, *sky_label_, depth_.options().vote_stride_px, &view);
  }
  cloud.camera_views = {std::make_shared<const DepthView>(std::move(view))};
  return cloud;
}

LabelledCloud StereoLabelStage::Process(const Frame& frame, const KeyframeLabels* keyframe_labels) {
  if (frame.depth) return ToCloud(frame, *frame.depth);
  return ToCloud(frame, ComputeDepth(frame, keyframe_labels));
}

FrameDepthStage::FrameDepthStage(std::unique_ptr<StereoLabelStage> stage, FrameDepthSink* sink)
    : stage_(std::move(stage)), sink_(sink) {
  SEMAP_ASSERT(stage_ != nullptr && sink_ != nullptr, "a depth node's stage needs a stage and a sink");
}

LabelledCloud FrameDepthStage::Process(const Frame& frame, const KeyframeLabels* keyframe_labels) {
  sink_->OnFrameDepth(frame, stage_->ComputeDepth(frame, keyframe_labels));
  LabelledCloud none;
  none.camera_frame_ids = {frame.id};
  return none;
}

MapUpdate NoMapStage::Process(const LabelledCloud& cloud, const Pose3d&) {
  last_frame_id_ = cloud.camera_frame_ids.empty() ? last_frame_id_ + 1 : cloud.camera_frame_ids.front();
  MapUpdate u;
  u.frame_id = last_frame_id_;
  return u;
}

MapUpdate NoMapStage::Finish() {
  MapUpdate u;
  u.frame_id = last_frame_id_;
  return u;
}

WindowedSimplifyStage::WindowedSimplifyStage(const SimplifyOptions& options, ClassMap class_map)
    : simplifier_(options, std::move(class_map)) {}

LabelledCloud WindowedSimplifyStage::Process(LabelledCloud cloud, std::vector<ClassPointCount>* counts) {
  auto result = simplifier_.Process(cloud);
  for (const auto& c : result.result.per_class) {
    counts->push_back({c.label, static_cast<std::int64_t>(c.in), static_cast<std::int64_t>(c.kept)});
  }
  return std::move(result.kept);
}

IncrementalMapStage::IncrementalMapStage(const MapOptions& options, int mesh_every_frames)
    : map_(options), mesh_every_frames_(mesh_every_frames) {
  SEMAP_ASSERT(mesh_every_frames >= 1, "mesh_every_frames " << mesh_every_frames);
}

MapUpdate IncrementalMapStage::Process(const LabelledCloud& cloud, const Pose3d&) {
  // The cloud's camera (its frame's left camera) is where every ray of this frame starts.
  const MapUpdateResult r = map_.Update(cloud);
  last_frame_id_ = cloud.camera_frame_ids.empty() ? last_frame_id_ + 1 : cloud.camera_frame_ids.front();
  const Stopwatch stopwatch;
  // Every mesh_every_frames frames of the sequence, whether or not the frames between were integrated (a
  // realtime run's drops do not slow the mesh's cadence down).
  if (!next_mesh_frame_id_) next_mesh_frame_id_ = last_frame_id_ + mesh_every_frames_ - 1;
  const bool with_mesh = last_frame_id_ >= *next_mesh_frame_id_;
  if (with_mesh) next_mesh_frame_id_ = last_frame_id_ + mesh_every_frames_;
  MapUpdate u = Report(with_mesh);
  const double mesh_ms = stopwatch.ElapsedMs();
  u.steps = {{"locate", r.locate_ms}, {"insert", r.insert_ms},     {"votes", r.trace_ms},
             {"carve", r.carve_ms},   {"finalise", r.finalise_ms}, {"mesh", mesh_ms}};
  return u;
}

MapUpdate IncrementalMapStage::Finish() {
  map_.InsertHeldPoints();  // the stream ended: no later frame will confirm the far points still held
  return Report(/*with_mesh=*/true);
}

MapUpdate IncrementalMapStage::Report(bool with_mesh) {
  MapUpdate u;
  u.frame_id = last_frame_id_;
  if (with_mesh) {
    u.mesh.emplace();
    u.mesh->finalised = map_.TakeFinalisedMesh();
    u.mesh->live = map_.ExtractIdentifiedMesh();
  }
  const MapStatistics s = map_.Sizes();
  u.vertices = static_cast<std::int64_t>(s.num_points + s.num_steiner_vertices);
  u.cells = static_cast<std::int64_t>(s.num_cells);
  u.rays = static_cast<std::int64_t>(s.num_rays);
  return u;
}

}  // namespace semap
