// Test helpers: a randomly evolving mesh (triangles added, removed and finalised every step, as the map does)
// and a mesh as a comparable triangle soup.
#pragma once

#include <map>
#include <random>
#include <set>
#include <vector>

#include "engine/core/mesh_delta.h"

namespace semap::test {

// A mesh over vertex ids, vertex id i at a position exactly representable in float, spread over ~40 m.
inline IdentifiedMesh MeshOfIds(const std::vector<std::array<VertexId, 3>>& tris) {
  IdentifiedMesh m;
  std::map<VertexId, std::uint32_t> index;
  for (const auto& t : tris) {
    std::array<std::uint32_t, 3> local{};
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = index.emplace(t[k], static_cast<std::uint32_t>(m.vertex_ids.size()));
      if (inserted) {
        const VertexId i = t[k];
        m.vertex_ids.push_back(i);
        m.mesh.vertices.emplace_back(0.125 * double((i * 7919) % 320), 0.125 * double((i * 104729) % 160),
                                     0.25 * double(i % 9));
        m.mesh.labels.push_back(static_cast<Label>(i % 20));
        m.mesh.colors_rgb.push_back({static_cast<std::uint8_t>(i % 256), 7, 9});
      }
      local[k] = it->second;
    }
    m.mesh.triangles.push_back(local);
  }
  return m;
}

// Every Step: some live triangles removed, some finalised, new ones added; truth() accumulates the deltas.
class EvolvingMesh {
 public:
  explicit EvolvingMesh(unsigned seed) : rng_(seed) {}

  MeshDelta Step(std::int64_t frame) {
    std::vector<std::array<VertexId, 3>> frozen;
    for (auto it = live_.begin(); it != live_.end();) {
      const auto r = rng_() % 10;
      if (r == 0) {
        it = live_.erase(it);
      } else if (r == 1 && frame > 3) {
        frozen.push_back(*it);
        it = live_.erase(it);
      } else {
        ++it;
      }
    }
    const int adds = 10 + static_cast<int>(rng_() % 20);
    for (int a = 0; a < adds; ++a) {
      const VertexId b = next_vertex_;
      next_vertex_ += 2;
      // Shares a vertex with the previous triangle now and then (meshes share vertices).
      live_.insert({b, b + 1, rng_() % 3 == 0 && b > 2 ? b - 1 : b + 2});
    }
    MeshDelta d = differ_.Update(frame, MeshOfIds({live_.begin(), live_.end()}), MeshOfIds(frozen));
    truth_.Apply(d);
    return d;
  }
  const MeshAccumulator& truth() const { return truth_; }

 private:
  std::mt19937 rng_;
  std::set<std::array<VertexId, 3>> live_;
  VertexId next_vertex_ = 1;
  MeshDiffer differ_;
  MeshAccumulator truth_;
};

// The mesh as a multiset of triangles by vertex positions, each rotated to start at its smallest vertex.
inline std::multiset<std::array<double, 9>> Soup(const Mesh& m) {
  std::multiset<std::array<double, 9>> out;
  for (const auto& t : m.triangles) {
    std::array<std::array<double, 3>, 3> v;
    for (int k = 0; k < 3; ++k) v[k] = {m.vertices[t[k]].x(), m.vertices[t[k]].y(), m.vertices[t[k]].z()};
    const int first = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
    std::array<double, 9> s{};
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) s[3 * k + c] = v[(first + k) % 3][c];
    }
    out.insert(s);
  }
  return out;
}

}  // namespace semap::test
