// `semap eval-poses`: an estimated camera trajectory (e.g. a run's poses_odometry.txt) against the sequence's
// own poses.
#pragma once

#include <filesystem>
#include <string>

#include "app/config/config.h"
#include "engine/eval/trajectory_metrics.h"

namespace semap::app {

struct PoseEvaluation {
  int frames = 0;
  double path_length_m = 0.0;  // of the sequence's poses
  KittiOdometryError kitti;    // segments of 100-800 m (none on a shorter drive)
  RelativePoseError relative;  // over 10-frame windows
  AbsoluteTrajectoryError absolute;
};

// Frames per relative-error window (`semap eval-poses`).
constexpr int kRelativeErrorFrames = 10;

// Reads the frames config.input selects from `dataset` (they must have poses) and the estimate `poses`: KITTI
// pose format, one line per selected frame, or TUM (".tum"; each frame takes the pose with the nearest
// timestamp, within half the smallest frame period). Throws io::FileError naming the file, or
// std::runtime_error naming the first frame without a pose.
PoseEvaluation EvaluatePoses(const Config& config, const std::string& dataset,
                             const std::filesystem::path& poses);

// The evaluation as text (one figure a line) and as JSON.
std::string PoseEvaluationText(const PoseEvaluation& e);
std::string PoseEvaluationJson(const PoseEvaluation& e);

}  // namespace semap::app
