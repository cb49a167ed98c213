// What travels between the pipeline's threads: one frame's item, a keyframe's segmentation job, and the
// outcomes of frames that leave before the stages. Plain data, owned by one thread at a time (handed over
// through the queues).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/pipeline/pipeline.h"

namespace semap::pipeline_internal {

using Clock = std::chrono::steady_clock;

inline double MsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Milliseconds between two readings of a PipelineClock (seconds).
inline double MsFromTo(double from_s, double to_s) { return 1000.0 * (to_s - from_s); }

enum StageIndex { kRead, kDepth, kSimplify, kMap, kNumStages };
inline constexpr std::array<const char*, kNumStages> kStageNames = {"read", "depth", "simplify", "map"};
// "segment": the keyframes' segmentation; "depth.label_wait": a depth worker waiting for it.
inline constexpr const char* kSegmentStageName = "segment";
inline constexpr const char* kLabelWaitStepName = "depth.label_wait";
inline constexpr int kNumDropReasons = 3;  // DropReason's values
inline constexpr int kNumLatencySteps = static_cast<int>(std::size(kLatencyStepNames));

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

// When a frame's results were ready, on the pipeline's clock (s): what FrameLatency is measured from.
struct ClockTimes {
  double due_s = 0.0;      // realtime: when the frame was due
  double sensor_s = 0.0;   // the frame's sensor time: due_s in realtime mode, when it was read otherwise
  double entered_s = 0.0;  // when it entered the input queue
  double depth_s = 0.0;
  double labels_s = 0.0;
  double map_s = 0.0;
};

// One frame travelling through the stages.
struct Item {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  std::int64_t seq = 0;          // position in the stream of frames the depth workers took
  std::unique_ptr<Frame> frame;  // until the depth stage
  // With a segment stage: the labels of this frame's keyframe (until the depth stage), whether the frame is
  // a keyframe itself, the segmenter's time on it and the depth worker's wait for the labels.
  std::shared_future<SegmentResult> keyframe_labels;
  // Realtime: the newest keyframe's labels that were ready when the frame was read (may be none), taken when
  // keyframe_labels are not ready yet.
  std::shared_future<SegmentResult> ready_labels;
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
  ClockTimes times;
  bool failed() const { return !error.empty(); }
};

// What happened to a frame outside the stages' flow: dropped from the input queue, or a failed read that a
// newer frame took the place of.
struct SideEvent {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  std::optional<DropReason> dropped;  // else failed in `stage`
  std::string stage;
  std::string what;
};

// The queues' occupancy when a frame came out of the map (items waiting in front of each stage).
struct QueueSizes {
  int segment = 0;
  int depth = 0;
  int simplify = 0;
  int map = 0;
};

}  // namespace semap::pipeline_internal
