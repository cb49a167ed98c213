#include "engine/pipeline/internal/pose_check.h"

#include <algorithm>
#include <cstdio>

namespace semap::pipeline_internal {

namespace {
// |RᵀR − I| above this (any entry) is not a rotation: far above float round-off in a pose file.
constexpr double kMaxOrthogonalityError = 1e-3;
}  // namespace

std::string PoseProblem(const Pose3d& pose, double timestamp_s, const std::optional<AcceptedPose>& last,
                        double max_speed_mps, double min_frame_period_s) {
  if (!pose.matrix().allFinite()) return "pose is not finite (NaN or inf)";
  const Eigen::Matrix3d r = pose.linear();
  const double orthogonality_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality_error > kMaxOrthogonalityError || r.determinant() <= 0.0) {
    return "pose rotation is not a rotation (|RᵀR - I| = " + std::to_string(orthogonality_error) + ", det " +
           std::to_string(r.determinant()) + ")";
  }
  if (!last || max_speed_mps <= 0.0) return "";
  const double dt_s = std::max(timestamp_s - last->timestamp_s, min_frame_period_s);
  const double moved_m = (pose.translation() - last->position).norm();
  if (moved_m <= max_speed_mps * dt_s) return "";
  char text[256];
  std::snprintf(text, sizeof(text),
                "pose jumps %.1f m in %.2f s since frame %lld (%.0f m/s > max_speed_mps %.0f)", moved_m, dt_s,
                static_cast<long long>(last->frame_id), moved_m / dt_s, max_speed_mps);
  return text;
}

}  // namespace semap::pipeline_internal
