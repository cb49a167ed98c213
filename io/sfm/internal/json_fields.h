// Typed access to the members of a JSON object read from a reconstruction file, each failure a ParseError
// naming the file, the entry and the field path (e.g. "views[3] (viewId 17): extrinsic.rotation[1]").
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/sfm/internal/sfm_checks.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::io::sfm_internal {

// Parses a whole JSON file; throws FileError for a missing/unreadable file or invalid JSON (with the
// byte offset of the syntax error).
nlohmann::json ReadJsonFile(const std::filesystem::path& path);
// Writes `j` (indented); throws FileError when the file cannot be written.
void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& j);

// One JSON object of an entry; `prefix` is its field path inside the entry ("" or "extrinsic.").
class JsonObject {
 public:
  // Throws unless `value` is an object (the error names `prefix` without its trailing dot).
  JsonObject(const nlohmann::json& value, const EntryRef* at, std::string prefix = "");

  bool Has(const char* key) const { return value_->contains(key); }
  // The member; throws "missing" when absent.
  const nlohmann::json& Get(const char* key) const;
  JsonObject Object(const char* key) const;
  // Must be an array (of any elements).
  const nlohmann::json& Array(const char* key) const;
  // An integer in [min, max].
  std::int64_t Int(const char* key, std::int64_t min = INT64_MIN, std::int64_t max = INT64_MAX) const;
  double Number(const char* key) const;  // finite
  std::string String(const char* key) const;
  // Arrays of finite numbers of the given length; Numbers: any length.
  Eigen::Vector2d Vec2(const char* key) const;
  Eigen::Vector3d Vec3(const char* key) const;
  std::vector<double> Numbers(const char* key) const;
  // A 3×3 matrix as three rows of three numbers ([[r00, r01, r02], [r10, ...], ...]).
  Eigen::Matrix3d RowMatrix3(const char* key) const;

  std::string Field(const char* key) const { return prefix_ + key; }
  const EntryRef& at() const { return *at_; }
  const nlohmann::json& json() const { return *value_; }

 private:
  std::vector<double> NumberArray(const char* key, int expected_size) const;
  const nlohmann::json* value_;
  const EntryRef* at_;
  std::string prefix_;
};

// The document of a reconstruction file: checks its version member (`version_key` must be "0.2" or "0.3")
// and reads the optional "root_path" into r->image_root.
void ReadVersionAndRoot(const JsonObject& root, const char* version_key, SfmReconstruction* r);

// The element `i` of array `array` (named `field`) as an object.
JsonObject ArrayObject(const nlohmann::json& array, std::size_t i, const EntryRef* at,
                       const std::string& field);

}  // namespace semap::io::sfm_internal
