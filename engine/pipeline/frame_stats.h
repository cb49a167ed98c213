// What the streaming engine reports per frame. Plain data; filled by the pipeline, never by the stages.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/class_map.h"

namespace semap {

struct StageTiming {
  std::string name;
  double last_ms = 0.0;  // this frame
  double mean_ms = 0.0;  // over the run so far
  double p50_ms = 0.0;
  double p95_ms = 0.0;
  double max_ms = 0.0;
  int queue_occupancy = 0;  // items waiting in the queue in front of the stage (a step has none: 0)
};

// A step inside a stage is named "stage.step" (e.g. "map.votes"): it has a time but no queue of its own.
inline bool IsStageStep(const std::string& name) { return name.find('.') != std::string::npos; }

struct ClassPointCount {
  Label label = 0;
  std::int64_t in = 0;
  std::int64_t kept = 0;
};

// How old a frame's results were when each step had them, ms: from the frame's sensor time (realtime mode:
// when the frame was due on the pipeline's clock; exhaustive mode: when the reader had read it).
struct FrameLatency {
  double late_ms = 0.0;       // realtime: the frame entered the pipeline this long after it was due (reading
                              // it took longer than the time left before its due time); exhaustive: 0
  double depth_ms = 0.0;      // its depth (and labelled points) ready
  double labels_ms = 0.0;     // its labels ready (its keyframe's, with a segment stage; else with the depth)
  double map_ms = 0.0;        // integrated in the map
  double published_ms = 0.0;  // the mesh change that contains it handed to the sinks
};

// The steps FrameLatency measures, in its order, as frames.csv and summary.json name them.
inline constexpr const char* kLatencyStepNames[] = {"depth", "labels", "map", "published"};

struct FrameStats {
  std::int64_t frame_id = -1;
  double timestamp_s = 0.0;
  std::int64_t frames_processed = 0;
  std::int64_t frames_dropped = 0;
  std::int64_t frames_failed = 0;
  // Frames not integrated because the engine was behind, by reason ("behind": a newer frame took its place
  // in the input queue; "no_keyframe_labels": no keyframe had labels yet), counted in frames_dropped.
  std::vector<std::pair<std::string, std::int64_t>> dropped_by_reason;
  double elapsed_s = 0.0;  // since the first frame entered the pipeline
  double fps = 0.0;        // frames_processed / elapsed_s: the paper's frame rate
  std::vector<StageTiming> stages;
  FrameLatency latency;  // this frame
  // kLatencyStepNames' latencies over the run so far (last_ms: this frame's; no queue).
  std::vector<StageTiming> latencies;
  std::int64_t points_in = 0;                 // this frame, before simplification
  std::int64_t points_kept = 0;               // this frame, after simplification
  std::vector<ClassPointCount> class_counts;  // this frame
  std::int64_t map_vertices = 0;
  std::int64_t map_cells = 0;
  std::int64_t map_rays = 0;
  std::int64_t mesh_triangles = 0;
  double rss_mb = 0.0;
  double cpu_s = 0.0;  // CPU time of the whole process so far (all threads): unlike elapsed_s, not slowed by
                       // other processes sharing the cores
};

}  // namespace semap
