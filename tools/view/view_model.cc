#include "tools/view/view_model.h"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>

namespace semap::tools::view {
namespace {

template <typename T>
void Append(std::string* out, const T& value) {
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));  // the page reads little-endian (x86, ARM)
}

}  // namespace

std::string EncodeMeshMessage(const Mesh& mesh, std::int64_t frame_id, const std::vector<float>* error_m) {
  const auto n = static_cast<std::uint32_t>(mesh.num_vertices());
  const auto m = static_cast<std::uint32_t>(mesh.num_triangles());
  const bool with_error = error_m != nullptr && error_m->size() == n;
  std::string out;
  out.reserve(24 + n * (12 + (with_error ? 4 : 0) + 4) + m * 12);
  out.append("SMV1", 4);
  Append(&out, n);
  Append(&out, m);
  Append(&out, std::uint32_t{with_error ? 1u : 0u});
  Append(&out, frame_id);
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) Append(&out, static_cast<float>(v[k]));
  }
  if (with_error) out.append(reinterpret_cast<const char*>(error_m->data()), n * sizeof(float));
  for (const auto& t : mesh.triangles) {
    for (std::uint32_t i : t) Append(&out, i);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto c =
        i < mesh.colors_rgb.size() ? mesh.colors_rgb[i] : std::array<std::uint8_t, 3>{200, 200, 200};
    out.append(reinterpret_cast<const char*>(c.data()), 3);
  }
  for (std::uint32_t i = 0; i < n; ++i)
    out.push_back(static_cast<char>(i < mesh.labels.size() ? mesh.labels[i] : 0));
  return out;
}

ViewModel::ViewModel(SourceInfo info, const ClassMap& class_map) {
  nlohmann::json j;
  j["type"] = "hello";
  j["kind"] = info.kind;
  j["name"] = info.name;
  j["up"] = info.up;
  j["has_error"] = info.has_error;
  j["error_source"] = info.error_source;
  j["class_scheme"] = class_map.scheme();
  j["palette"] = nlohmann::json::array();
  for (const SemanticClass& c : class_map.classes()) {
    j["palette"].push_back({{"id", c.id}, {"name", c.name}, {"rgb", c.color_rgb}});
  }
  hello_ = j.dump();
}

void ViewModel::SetMesh(std::shared_ptr<const std::string> encoded, std::int64_t triangles,
                        std::int64_t vertices) {
  std::lock_guard lock(mutex_);
  mesh_ = std::move(encoded);
  triangles_ = triangles;
  vertices_ = vertices;
  ++mesh_version_;
}

void ViewModel::AddStats(const StatsPoint& s) {
  std::lock_guard lock(mutex_);
  stats_.push_back(s);
}

void ViewModel::AddPose(const PosePoint& p) {
  std::lock_guard lock(mutex_);
  poses_.push_back(p);
}

void ViewModel::SetStatus(const std::string& text) {
  std::lock_guard lock(mutex_);
  if (text == status_) return;
  status_ = text;
  ++status_version_;
}

void ViewModel::Reset() {
  std::lock_guard lock(mutex_);
  ++epoch_;
  mesh_.reset();
  ++mesh_version_;
  triangles_ = vertices_ = 0;
  stats_.clear();
  poses_.clear();
}

ViewModel::Snapshot ViewModel::Get() const {
  std::lock_guard lock(mutex_);
  return {epoch_,          mesh_version_, mesh_,         triangles_,   vertices_,
          status_version_, status_,       stats_.size(), poses_.size()};
}

std::string ViewModel::StatsSince(size_t from, size_t to) const {
  std::lock_guard lock(mutex_);
  to = std::min(to, stats_.size());
  if (from >= to) return "";
  nlohmann::json j;
  j["type"] = "stats";
  auto& points = j["points"] = nlohmann::json::array();
  for (size_t i = from; i < to; ++i) {
    const StatsPoint& s = stats_[i];
    points.push_back({s.frame_id, s.elapsed_s, s.fps, s.triangles, s.vertices});
  }
  return j.dump();
}

std::string ViewModel::PosesSince(size_t from, size_t to) const {
  std::lock_guard lock(mutex_);
  to = std::min(to, poses_.size());
  if (from >= to) return "";
  nlohmann::json j;
  j["type"] = "poses";
  auto& points = j["points"] = nlohmann::json::array();
  for (size_t i = from; i < to; ++i) {
    const PosePoint& p = poses_[i];
    const Eigen::Quaterniond& q = p.world_from_cam;
    points.push_back(
        {p.frame_id, p.position_m.x(), p.position_m.y(), p.position_m.z(), q.w(), q.x(), q.y(), q.z()});
  }
  return j.dump();
}

}  // namespace semap::tools::view
