// Checks shared by the reconstruction readers: where an error is (file, entry), rotations, finite values,
// file ids → indices.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <unordered_map>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io::sfm_internal {

// Largest |RᵀR − I| entry and |det R − 1| accepted for a rotation read from a file: writers print 6 to 17
// digits (ORB-SLAM writes floats), a rotation that is off by more is a wrong matrix, not rounding.
inline constexpr double kRotationTolerance = 1e-3;
// Largest | |q| − 1 | accepted for a COLMAP quaternion (it is normalised after the check).
inline constexpr double kQuaternionTolerance = 1e-3;

// An entry of a file being read (a line, a JSON object, a binary record): errors name both.
struct EntryRef {
  std::filesystem::path file;
  std::string entry;

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw ParseError(file, entry, field, problem);
  }
};

// `value` as text for error messages (shortest round-trip form).
std::string NumberText(double value);

// Throws unless every value is finite ("must be finite (got nan)").
void CheckFinite(const EntryRef& at, const std::string& field, const double* values, int count);

// Throws unless R is finite, orthonormal and a proper rotation (det +1), within kRotationTolerance.
void CheckRotation(const EntryRef& at, const std::string& field, const Eigen::Matrix3d& R);

// world_from_cam of a camera given as (rotation world → camera, centre in the world): the OpenMVG and SLAM
// JSON convention, x_cam = R (X − C).
Pose3d PoseFromRotationAndCenter(const Eigen::Matrix3d& cam_from_world_rotation,
                                 const Eigen::Vector3d& center);

// An optional member that entries must all have or all lack (semap's "label"): the first entry decides.
class AllOrNone {
 public:
  explicit AllOrNone(std::string entries) : entries_(std::move(entries)) {}
  // Throws "present, but earlier <entries> have none" / "missing, but earlier <entries> have one".
  void Check(const EntryRef& at, const std::string& field, bool present);

 private:
  std::string entries_;
  int state_ = -1;  // -1 undecided, 0 none, 1 all
};

// File ids of one kind of entry (views, points, intrinsics) → their index in the reconstruction.
class IdIndex {
 public:
  explicit IdIndex(std::string what) : what_(std::move(what)) {}
  // Throws naming both entries' id when `id` was added before.
  void Add(const EntryRef& at, const std::string& field, std::int64_t id, std::uint32_t index);
  std::optional<std::uint32_t> Find(std::int64_t id) const;
  // The index of `id`; throws "<what> <id> does not exist" otherwise.
  std::uint32_t Get(const EntryRef& at, const std::string& field, std::int64_t id) const;
  std::size_t size() const { return index_.size(); }

 private:
  std::string what_;
  std::unordered_map<std::int64_t, std::uint32_t> index_;
};

}  // namespace semap::io::sfm_internal
