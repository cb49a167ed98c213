#include "engine/core/mesh_delta.h"

#include <algorithm>
#include <map>
#include <set>
#include <unordered_set>
#include <utility>

#include "engine/core/check.h"

namespace semap {

std::array<VertexId, 3> CanonicalTriangle(const std::array<VertexId, 3>& t) {
  const int first = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
  return {t[first], t[(first + 1) % 3], t[(first + 2) % 3]};
}

size_t MeshDiffer::KeyHash::operator()(const std::array<VertexId, 3>& k) const {
  size_t h = std::hash<VertexId>()(k[0]);
  h ^= std::hash<VertexId>()(k[1]) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  h ^= std::hash<VertexId>()(k[2]) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  return h;
}

namespace {

// Adds to `delta` the vertex `index` of `m` unless already there.
void AddVertex(const IdentifiedMesh& m, std::uint32_t index, std::unordered_set<VertexId>* seen,
               MeshDelta* delta) {
  const VertexId id = m.vertex_ids[index];
  if (!seen->insert(id).second) return;
  delta->vertex_ids.push_back(id);
  delta->vertex_positions.push_back(m.mesh.vertices[index]);
  if (!m.mesh.colors_rgb.empty()) delta->vertex_colors_rgb.push_back(m.mesh.colors_rgb[index]);
  if (!m.mesh.labels.empty()) delta->vertex_labels.push_back(m.mesh.labels[index]);
}

std::array<VertexId, 3> KeyOf(const IdentifiedMesh& m, const std::array<std::uint32_t, 3>& t) {
  return CanonicalTriangle({m.vertex_ids[t[0]], m.vertex_ids[t[1]], m.vertex_ids[t[2]]});
}

}  // namespace

MeshDelta MeshDiffer::Update(std::int64_t frame_id, const IdentifiedMesh& live,
                             const IdentifiedMesh& frozen) {
  SEMAP_ASSERT(live.vertex_ids.size() == live.mesh.vertices.size());
  SEMAP_ASSERT(frozen.vertex_ids.size() == frozen.mesh.vertices.size());
  MeshDelta delta;
  delta.frame_id = frame_id;
  std::unordered_set<VertexId> seen_vertices;

  // Frozen triangles: publish those never published, then forget them (they are never removed).
  for (const auto& t : frozen.mesh.triangles) {
    const auto key = KeyOf(frozen, t);
    if (const auto it = live_.find(key); it != live_.end()) {  // already published while live
      delta.finalised_triangle_ids.push_back(it->second.id);
      live_.erase(it);
      continue;
    }
    delta.finalised_triangle_ids.push_back(next_id_);
    delta.added_triangle_ids.push_back(next_id_++);
    delta.added_triangles.push_back(key);
    for (auto i : t) AddVertex(frozen, i, &seen_vertices, &delta);
  }

  // The live set is updated in place: a triangle still there is stamped with this update's generation,
  // a new one is added, and those left unstamped afterwards disappeared. Rebuilding the set every update
  // would allocate and free a node per live triangle (~5·10^5 on a long drive).
  ++generation_;
  // Grown ahead when the live mesh outgrows the table, never shrunk: libstdc++'s reserve() also shrinks, and
  // rehashed the whole table on every update whose mesh was smaller than the one before.
  if (double(live.mesh.triangles.size()) > double(live_.bucket_count()) * live_.max_load_factor()) {
    live_.reserve(live.mesh.triangles.size());
  }
  for (const auto& t : live.mesh.triangles) {
    const auto key = KeyOf(live, t);
    const auto [it, inserted] = live_.try_emplace(key, LiveTriangle{0, generation_});
    if (!inserted) {
      it->second.seen = generation_;  // still there (or a duplicate in the input: published once)
      continue;
    }
    it->second.id = next_id_++;
    delta.added_triangle_ids.push_back(it->second.id);
    delta.added_triangles.push_back(key);
    for (auto i : t) AddVertex(live, i, &seen_vertices, &delta);
  }
  for (auto it = live_.begin(); it != live_.end();) {
    if (it->second.seen == generation_) {
      ++it;
      continue;
    }
    delta.removed_triangle_ids.push_back(it->second.id);
    it = live_.erase(it);
  }
  std::sort(delta.removed_triangle_ids.begin(), delta.removed_triangle_ids.end());
  return delta;
}

void MeshAccumulator::Reset() {
  vertices_.clear();
  triangles_.clear();
  has_colors_ = has_labels_ = false;
}

void MeshAccumulator::Apply(const MeshDelta& delta) {
  SEMAP_ASSERT(delta.vertex_positions.size() == delta.vertex_ids.size());
  SEMAP_ASSERT(delta.added_triangles.size() == delta.added_triangle_ids.size());
  for (auto id : delta.removed_triangle_ids) {
    const auto it = triangles_.find(id);
    if (it == triangles_.end()) continue;
    const std::array<VertexId, 3> t = it->second;
    triangles_.erase(it);
    Reference(t, -1);
  }
  has_colors_ = has_colors_ || !delta.vertex_colors_rgb.empty();
  has_labels_ = has_labels_ || !delta.vertex_labels.empty();
  for (size_t i = 0; i < delta.vertex_ids.size(); ++i) {
    Vertex& v = vertices_[delta.vertex_ids[i]];
    v.position = delta.vertex_positions[i];
    if (!delta.vertex_colors_rgb.empty()) v.color_rgb = delta.vertex_colors_rgb[i];
    if (!delta.vertex_labels.empty()) v.label = delta.vertex_labels[i];
  }
  for (size_t i = 0; i < delta.added_triangle_ids.size(); ++i) {
    const auto [it, inserted] = triangles_.try_emplace(delta.added_triangle_ids[i], delta.added_triangles[i]);
    if (!inserted) {  // the same id again (a snapshot over what is held): the new vertices replace the old
      Reference(delta.added_triangles[i], +1);
      Reference(std::exchange(it->second, delta.added_triangles[i]), -1);
      continue;
    }
    Reference(it->second, +1);
  }
  // Vertices that came without a triangle (or whose triangles all went) are not kept.
  for (auto id : delta.vertex_ids) {
    const auto it = vertices_.find(id);
    if (it != vertices_.end() && it->second.triangles == 0) vertices_.erase(it);
  }
}

void MeshAccumulator::Reference(const std::array<VertexId, 3>& t, int step) {
  for (auto id : t) {
    const auto it = vertices_.find(id);
    SEMAP_ASSERT(it != vertices_.end(), "triangle references unknown vertex " << id);
    it->second.triangles += step;
    if (it->second.triangles == 0) vertices_.erase(it);
  }
}

void MeshAccumulator::AppendVertex(VertexId id, MeshDelta* delta) const {
  const Vertex& v = vertices_.at(id);
  delta->vertex_ids.push_back(id);
  delta->vertex_positions.push_back(v.position);
  if (has_colors_) delta->vertex_colors_rgb.push_back(v.color_rgb);
  if (has_labels_) delta->vertex_labels.push_back(v.label);
}

Mesh MeshAccumulator::ToMesh() const {
  // Deterministic output: triangles by id, vertices by id.
  std::map<TriangleId, std::array<VertexId, 3>> ordered(triangles_.begin(), triangles_.end());
  std::map<VertexId, std::uint32_t> index;
  for (const auto& [id, t] : ordered) {
    for (auto v : t) index.emplace(v, 0);
  }
  Mesh mesh;
  for (auto& [vid, idx] : index) {
    const Vertex& v = vertices_.at(vid);
    idx = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(v.position);
    if (has_colors_) mesh.colors_rgb.push_back(v.color_rgb);
    if (has_labels_) mesh.labels.push_back(v.label);
  }
  for (const auto& [id, t] : ordered) mesh.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return mesh;
}

MeshDelta MeshAccumulator::AsSnapshot(std::int64_t frame_id) const {
  MeshDelta d;
  d.frame_id = frame_id;
  std::map<TriangleId, std::array<VertexId, 3>> ordered(triangles_.begin(), triangles_.end());
  std::set<VertexId> used;
  for (const auto& [id, t] : ordered) {
    d.added_triangle_ids.push_back(id);
    d.added_triangles.push_back(t);
    used.insert(t.begin(), t.end());
  }
  for (const VertexId id : used) AppendVertex(id, &d);
  return d;
}

MeshDelta MeshAccumulator::TakeTriangles(const std::vector<TriangleId>& ids) {
  MeshDelta d;
  std::unordered_set<VertexId> appended;
  for (const TriangleId id : ids) {
    const auto it = triangles_.find(id);
    if (it == triangles_.end()) continue;
    d.added_triangle_ids.push_back(id);
    d.added_triangles.push_back(it->second);
    for (auto v : it->second) {
      if (appended.insert(v).second) AppendVertex(v, &d);
    }
  }
  // Forgotten after all are listed: a vertex may be on several of them.
  for (std::size_t i = 0; i < d.added_triangle_ids.size(); ++i) {
    triangles_.erase(d.added_triangle_ids[i]);
    Reference(d.added_triangles[i], -1);
  }
  return d;
}

}  // namespace semap
