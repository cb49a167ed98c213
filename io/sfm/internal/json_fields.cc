#include "io/sfm/internal/json_fields.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace semap::io::sfm_internal {
namespace {

const char* TypeName(const nlohmann::json& j) { return j.is_null() ? "null" : j.type_name(); }

}  // namespace

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "file not found");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw FileError(path, "read error");
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {  // syntax errors, and numbers out of double range
    throw FileError(path, std::string("not valid JSON: ") + e.what());
  }
}

void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& j) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw FileError(path, "cannot open for writing");
  out << j.dump(1) << '\n';
  out.close();
  if (!out) throw FileError(path, "write failed");
}

JsonObject::JsonObject(const nlohmann::json& value, const EntryRef* at, std::string prefix)
    : value_(&value), at_(at), prefix_(std::move(prefix)) {
  if (!value.is_object()) {
    const std::string field = prefix_.empty() ? "" : prefix_.substr(0, prefix_.size() - 1);
    at_->Fail(field, std::string("must be an object (got ") + TypeName(value) + ")");
  }
}

const nlohmann::json& JsonObject::Get(const char* key) const {
  const auto it = value_->find(key);
  if (it == value_->end()) at_->Fail(Field(key), "missing");
  return *it;
}

JsonObject JsonObject::Object(const char* key) const { return JsonObject(Get(key), at_, Field(key) + "."); }

const nlohmann::json& JsonObject::Array(const char* key) const {
  const nlohmann::json& j = Get(key);
  if (!j.is_array()) at_->Fail(Field(key), std::string("must be an array (got ") + TypeName(j) + ")");
  return j;
}

std::int64_t JsonObject::Int(const char* key, std::int64_t min, std::int64_t max) const {
  const nlohmann::json& j = Get(key);
  std::int64_t v = 0;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(INT64_MAX)) at_->Fail(Field(key), "integer out of range");
    v = static_cast<std::int64_t>(u);
  } else if (j.is_number_integer()) {
    v = j.get<std::int64_t>();
  } else {
    at_->Fail(Field(key), std::string("must be an integer (got ") + TypeName(j) + " " + j.dump() + ")");
  }
  if (v < min || v > max) {
    at_->Fail(Field(key), "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "] (got " +
                              std::to_string(v) + ")");
  }
  return v;
}

double JsonObject::Number(const char* key) const {
  const nlohmann::json& j = Get(key);
  if (!j.is_number()) at_->Fail(Field(key), std::string("must be a number (got ") + TypeName(j) + ")");
  const double v = j.get<double>();
  CheckFinite(*at_, Field(key), &v, 1);
  return v;
}

std::string JsonObject::String(const char* key) const {
  const nlohmann::json& j = Get(key);
  if (!j.is_string()) at_->Fail(Field(key), std::string("must be a string (got ") + TypeName(j) + ")");
  return j.get<std::string>();
}

std::vector<double> JsonObject::NumberArray(const char* key, int expected_size) const {
  const nlohmann::json& j = Array(key);
  if (expected_size >= 0 && j.size() != static_cast<std::size_t>(expected_size)) {
    at_->Fail(Field(key), "must have " + std::to_string(expected_size) + " numbers (got " +
                              std::to_string(j.size()) + ")");
  }
  std::vector<double> out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string field = Field(key) + "[" + std::to_string(i) + "]";
    if (!j[i].is_number()) at_->Fail(field, std::string("must be a number (got ") + TypeName(j[i]) + ")");
    out.push_back(j[i].get<double>());
    CheckFinite(*at_, field, &out.back(), 1);
  }
  return out;
}

Eigen::Vector2d JsonObject::Vec2(const char* key) const {
  const auto v = NumberArray(key, 2);
  return {v[0], v[1]};
}

Eigen::Vector3d JsonObject::Vec3(const char* key) const {
  const auto v = NumberArray(key, 3);
  return {v[0], v[1], v[2]};
}

std::vector<double> JsonObject::Numbers(const char* key) const { return NumberArray(key, -1); }

Eigen::Matrix3d JsonObject::RowMatrix3(const char* key) const {
  const nlohmann::json& rows = Array(key);
  if (rows.size() != 3) at_->Fail(Field(key), "must have 3 rows (got " + std::to_string(rows.size()) + ")");
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    const std::string field = Field(key) + "[" + std::to_string(r) + "]";
    const nlohmann::json& row = rows[static_cast<std::size_t>(r)];
    if (!row.is_array() || row.size() != 3) at_->Fail(field, "must be a row of 3 numbers");
    for (int c = 0; c < 3; ++c) {
      const nlohmann::json& x = row[static_cast<std::size_t>(c)];
      const std::string cell = field + "[" + std::to_string(c) + "]";
      if (!x.is_number()) at_->Fail(cell, std::string("must be a number (got ") + TypeName(x) + ")");
      m(r, c) = x.get<double>();
      CheckFinite(*at_, cell, &m(r, c), 1);
    }
  }
  return m;
}

void ReadVersionAndRoot(const JsonObject& root, const char* version_key, SfmReconstruction* r) {
  const std::string version = root.String(version_key);
  if (version != "0.2" && version != "0.3")
    root.at().Fail(version_key, "'" + version + "' is not 0.2 or 0.3");
  if (root.Has("root_path")) r->image_root = root.String("root_path");
}

JsonObject ArrayObject(const nlohmann::json& array, std::size_t i, const EntryRef* at,
                       const std::string& field) {
  return JsonObject(array[i], at, field + "[" + std::to_string(i) + "].");
}

}  // namespace semap::io::sfm_internal
