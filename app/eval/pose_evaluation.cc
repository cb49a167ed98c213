#include "app/eval/pose_evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "io/frame_source.h"
#include "io/output/trajectory_files.h"

namespace semap::app {
namespace {

std::string Line(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Line(const char* format, ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof(text), format, args);
  va_end(args);
  return std::string(text) + "\n";
}

nlohmann::json DriftJson(const SegmentDrift& d) {
  return {{"length_m", d.length_m},
          {"segments", d.segments},
          {"translation_percent", d.translation_percent},
          {"rotation_deg_per_m", d.rotation_deg_per_m}};
}

}  // namespace

PoseEvaluation EvaluatePoses(const Config& config, const std::string& dataset,
                             const std::filesystem::path& poses) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  input.load_labels = false;
  const auto source = io::OpenFrameSource(dataset, input);
  std::vector<Pose3d> truth;
  std::vector<double> stamps;
  while (auto frame = source->Next()) {
    if (!frame->world_from_cam) {
      throw std::runtime_error(dataset + ": frame " + std::to_string(frame->id) +
                               " has no pose: nothing to evaluate the estimate against");
    }
    truth.push_back(*frame->world_from_cam);
    stamps.push_back(frame->timestamp_s);
  }
  std::vector<Pose3d> estimate;
  if (poses.extension() == ".tum") {
    const std::vector<io::StampedPose> tum = io::ReadTumTrajectory(poses);
    double period_s = std::numeric_limits<double>::infinity();
    for (size_t i = 1; i < stamps.size(); ++i)
      period_s = std::min(period_s, std::abs(stamps[i] - stamps[i - 1]));
    for (size_t i = 0; i < stamps.size(); ++i) {
      const auto best = std::min_element(tum.begin(), tum.end(), [&](const auto& a, const auto& b) {
        return std::abs(a.timestamp_s - stamps[i]) < std::abs(b.timestamp_s - stamps[i]);
      });
      if (best == tum.end() || std::abs(best->timestamp_s - stamps[i]) > period_s / 2) {
        throw io::FileError(poses, "no pose at the time of frame " + std::to_string(i) + " (" +
                                       std::to_string(stamps[i]) + " s)");
      }
      estimate.push_back(best->world_from_cam);
    }
  } else {
    estimate = io::ReadKittiPoses(poses);
    if (estimate.size() != truth.size()) {
      throw io::FileError(poses, "has " + std::to_string(estimate.size()) + " poses but the sequence has " +
                                     std::to_string(truth.size()) +
                                     " frames (input.first_frame / max_frames)");
    }
  }
  PoseEvaluation e;
  e.frames = static_cast<int>(truth.size());
  e.kitti = KittiOdometryMetric(truth, estimate);
  e.relative = RelativeError(truth, estimate, kRelativeErrorFrames);
  e.absolute = AbsoluteError(truth, estimate);
  e.path_length_m = e.absolute.path_length_m;
  return e;
}

std::string PoseEvaluationText(const PoseEvaluation& e) {
  std::string t = Line("frames: %d, path %.1f m", e.frames, e.path_length_m);
  if (e.kitti.overall.segments > 0) {
    t += Line("KITTI metric: %.3f %% translation, %.5f deg/m rotation (%d segments of 100-800 m)",
              e.kitti.overall.translation_percent, e.kitti.overall.rotation_deg_per_m,
              e.kitti.overall.segments);
    for (const auto& d : e.kitti.per_length) {
      t += Line("  %4.0f m: %.3f %%, %.5f deg/m (%d segments)", d.length_m, d.translation_percent,
                d.rotation_deg_per_m, d.segments);
    }
  } else {
    t += Line("KITTI metric: none (the drive is shorter than 100 m)");
  }
  t += Line(
      "relative error over %d frames: %.3f %% translation, %.5f deg/m rotation (%d windows, mean %.1f m); "
      "RMSE %.3f m, %.4f deg",
      kRelativeErrorFrames, e.relative.drift.translation_percent, e.relative.drift.rotation_deg_per_m,
      e.relative.drift.segments, e.relative.drift.length_m, e.relative.translation_rmse_m,
      e.relative.rotation_rmse_deg);
  t += Line("ATE after alignment: RMSE %.3f m, mean %.3f m, max %.3f m", e.absolute.rmse_m, e.absolute.mean_m,
            e.absolute.max_m);
  t += Line("end point: %.3f m (%.2f %% of the path), %.3f deg", e.absolute.end_point_m,
            e.absolute.end_point_percent, e.absolute.end_rotation_deg);
  return t;
}

std::string PoseEvaluationJson(const PoseEvaluation& e) {
  nlohmann::json per_length = nlohmann::json::array();
  for (const auto& d : e.kitti.per_length) per_length.push_back(DriftJson(d));
  const nlohmann::json j = {{"frames", e.frames},
                            {"path_length_m", e.path_length_m},
                            {"kitti", {{"overall", DriftJson(e.kitti.overall)}, {"per_length", per_length}}},
                            {"relative",
                             {{"frames", kRelativeErrorFrames},
                              {"drift", DriftJson(e.relative.drift)},
                              {"translation_rmse_m", e.relative.translation_rmse_m},
                              {"rotation_rmse_deg", e.relative.rotation_rmse_deg}}},
                            {"absolute",
                             {{"rmse_m", e.absolute.rmse_m},
                              {"mean_m", e.absolute.mean_m},
                              {"max_m", e.absolute.max_m},
                              {"end_point_m", e.absolute.end_point_m},
                              {"end_point_percent", e.absolute.end_point_percent},
                              {"end_rotation_deg", e.absolute.end_rotation_deg}}}};
  return j.dump(2) + "\n";
}

}  // namespace semap::app
