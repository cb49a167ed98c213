// Visual odometry in a run: a frame reader that estimates each frame's pose from its stereo pair as the
// frames are read (engine/odometry), hands it to the map in place of the sequence's (input.poses), and keeps
// the trajectory and the per-frame figures for the run's outputs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "engine/odometry/stereo_odometry.h"
#include "engine/pipeline/stages.h"
#include "io/output/output_sinks.h"

namespace semap::app {

// What the odometry found on one frame.
struct OdometryRecord {
  std::int64_t frame_id = 0;
  double timestamp_s = 0.0;
  OdometryResult result;
  double wall_ms = 0.0;  // time of the odometry on the frame
};

// The odometry's records of a run. Thread-safe: the reader adds, the output thread reads.
class OdometryLog {
 public:
  void Add(OdometryRecord record);
  // frames.csv columns of a frame: odometry_status (0 first, 1 tracked, 2 bridged, 3 restarted),
  // odometry_features, odometry_inliers, odometry_cpu_ms, odometry_ms, odometry_disparity_offset_px and
  // odometry_disparity_offset_per_row_px (the offset the frame's motion used) and odometry_keyframe (1: the
  // frame became the reference the next frames are tracked from); empty for a frame it has not seen.
  std::vector<io::FrameFigure> Figures(std::int64_t frame_id) const;
  std::vector<OdometryRecord> Records() const;
  // Frames that were bridged or restarted (their poses are guesses).
  int failures() const;

 private:
  mutable std::mutex mutex_;
  std::vector<OdometryRecord> records_;  // by frame, in reading order
};

// Passes the frames of `source` on, each with the pose the odometry estimated for it when `replace_poses`
// (else with the source's own pose). A frame where tracking failed (OdometryStatus kBridged or kRestarted)
// gets a constant-velocity guess in the trajectory but, with replace_poses, does not reach the map: Next()
// throws a std::runtime_error saying so (the pipeline logs it, counts it as failed and goes on). The first
// frame's pose is the source's when it has one (the odometry then shares its world frame), else the identity.
// Called from one thread (the pipeline's reader).
class OdometryReader : public FrameReader {
 public:
  OdometryReader(std::unique_ptr<FrameReader> source, const StereoOdometryOptions& options,
                 bool replace_poses, std::shared_ptr<OdometryLog> log);
  std::optional<Frame> Next() override;

 private:
  std::unique_ptr<FrameReader> source_;
  StereoOdometryOptions options_;
  bool replace_poses_;
  std::shared_ptr<OdometryLog> log_;
  std::unique_ptr<StereoOdometry> odometry_;
};

// Whether a run with `config` on a sequence that has (or lacks) its own poses maps with odometry poses, and
// whether it runs the odometry at all (compare_odometry). Throws ConfigError naming input.poses when the
// sequence lacks the poses it asks for (`has_poses`, `layout_name` describe the sequence).
struct OdometryPlan {
  bool run = false;
  bool replace_poses = false;
};
OdometryPlan PlanOdometry(const Config& config, bool has_poses, bool raw_layout, const std::string& dataset);

// The odometry of a run on `dataset` as config.pose_input says (its plan from the dataset's description),
// with the log its reader fills; log is null when it does not run. Throws what PlanOdometry and
// io::DescribeDataset throw.
struct RunOdometry {
  OdometryPlan plan;
  std::shared_ptr<OdometryLog> log;
};
RunOdometry PrepareOdometry(const Config& config, const std::string& dataset);

// The trajectory files of a run with odometry in `dir`: poses_odometry.txt (KITTI pose format, one line per
// frame the odometry saw, the 3x4 world_from_cam row-major) and poses_odometry.tum (TUM: timestamp tx ty tz
// qx qy qz qw). Returns the paths written; throws io::FileError.
std::vector<std::filesystem::path> WriteOdometryTrajectory(const OdometryLog& log,
                                                           const std::filesystem::path& dir);

}  // namespace semap::app
