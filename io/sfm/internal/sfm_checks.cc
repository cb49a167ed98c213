#include "io/sfm/internal/sfm_checks.h"

#include <Eigen/LU>
#include <charconv>
#include <cmath>

namespace semap::io::sfm_internal {

std::string NumberText(double value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), value);
  return std::string(buf, r.ptr);
}

void CheckFinite(const EntryRef& at, const std::string& field, const double* values, int count) {
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite(values[i])) at.Fail(field, "must be finite (got " + NumberText(values[i]) + ")");
  }
}

void CheckRotation(const EntryRef& at, const std::string& field, const Eigen::Matrix3d& R) {
  CheckFinite(at, field, R.data(), 9);
  const double orthonormality = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality > kRotationTolerance) {
    at.Fail(field, "not an orthonormal rotation (|R^T R - I| reaches " + NumberText(orthonormality) + ")");
  }
  const double det = R.determinant();
  if (std::abs(det - 1.0) > kRotationTolerance) {
    at.Fail(field, "not a rotation (determinant " + NumberText(det) + ", a reflection?)");
  }
}

Pose3d PoseFromRotationAndCenter(const Eigen::Matrix3d& cam_from_world_rotation,
                                 const Eigen::Vector3d& center) {
  Pose3d world_from_cam = Pose3d::Identity();
  world_from_cam.linear() = cam_from_world_rotation.transpose();
  world_from_cam.translation() = center;
  return world_from_cam;
}

void AllOrNone::Check(const EntryRef& at, const std::string& field, bool present) {
  if (state_ < 0) state_ = present ? 1 : 0;
  if (present != (state_ == 1)) {
    at.Fail(field, present ? "present, but earlier " + entries_ + " have none"
                           : "missing, but earlier " + entries_ + " have one");
  }
}

void IdIndex::Add(const EntryRef& at, const std::string& field, std::int64_t id, std::uint32_t index) {
  if (!index_.emplace(id, index).second) {
    at.Fail(field, what_ + " id " + std::to_string(id) + " appears twice");
  }
}

std::optional<std::uint32_t> IdIndex::Find(std::int64_t id) const {
  const auto it = index_.find(id);
  if (it == index_.end()) return std::nullopt;
  return it->second;
}

std::uint32_t IdIndex::Get(const EntryRef& at, const std::string& field, std::int64_t id) const {
  const auto found = Find(id);
  if (!found) at.Fail(field, what_ + " " + std::to_string(id) + " does not exist");
  return *found;
}

}  // namespace semap::io::sfm_internal
