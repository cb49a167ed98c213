#include "tests/engine/map/manifold_checker.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <set>
#include <sstream>

namespace semap::test {
namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;
constexpr std::size_t kMaxErrors = 20;

void Add(ManifoldReport* r, const std::string& message) {
  if (r->errors.size() < kMaxErrors) r->errors.push_back(message);
}

}  // namespace

std::string ManifoldReport::Summary() const {
  std::ostringstream os;
  for (const auto& e : errors) os << e << "\n";
  return os.str();
}

ManifoldReport CheckManifold(const Mesh& mesh, bool allow_boundary) {
  ManifoldReport r;
  const std::size_t n = mesh.vertices.size();
  std::set<std::array<std::uint32_t, 3>> seen;
  std::map<Edge, int> directed;            // directed edge → count
  std::vector<std::vector<Edge>> link(n);  // per vertex: the opposite edges
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (tri[0] >= n || tri[1] >= n || tri[2] >= n) {
      Add(&r, "triangle " + std::to_string(t) + " has an index out of range");
      ++r.num_bad_triangles;
      continue;
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      Add(&r, "triangle " + std::to_string(t) + " repeats a vertex");
      ++r.num_bad_triangles;
      continue;
    }
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    if ((mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).norm() <= 0.0) {
      Add(&r, "triangle " + std::to_string(t) + " has zero area");
      ++r.num_bad_triangles;
    }
    auto key = tri;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {
      Add(&r, "triangle " + std::to_string(t) + " is a duplicate");
      ++r.num_bad_triangles;
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = tri[k], v = tri[(k + 1) % 3], w = tri[(k + 2) % 3];
      if (++directed[{u, v}] == 2) ++r.num_misoriented_edges;
      if (directed[{u, v}] > 1) {
        Add(&r, "directed edge " + std::to_string(u) + "->" + std::to_string(v) +
                    " used twice (inconsistent orientation or non-manifold edge)");
      }
      link[u].push_back({v, w});
    }
  }
  // Undirected edge counts.
  std::map<Edge, int> undirected;
  for (const auto& [e, count] : directed)
    undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}] += count;
  for (const auto& [e, count] : undirected) {
    if (count == 1) ++r.num_boundary_edges;
    if (count > 2 || (count == 1 && !allow_boundary)) {
      ++r.num_nonmanifold_edges;
      Add(&r, "edge " + std::to_string(e.first) + "-" + std::to_string(e.second) + " has " +
                  std::to_string(count) + " triangles");
    }
  }
  // Vertex links: the opposite edges must chain into one cycle (or one path at the boundary).
  for (std::uint32_t v = 0; v < n; ++v) {
    const auto& edges = link[v];
    if (edges.empty()) continue;
    std::map<std::uint32_t, int> degree;
    std::map<std::uint32_t, std::vector<std::size_t>> at;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      ++degree[edges[i].first];
      ++degree[edges[i].second];
      at[edges[i].first].push_back(i);
      at[edges[i].second].push_back(i);
    }
    int ends = 0;
    bool bad_degree = false;
    for (const auto& [w, d] : degree) {
      if (d == 1) ++ends;
      if (d > 2) bad_degree = true;
    }
    if (bad_degree || (ends != 0 && !(allow_boundary && ends == 2))) {
      Add(&r, "vertex " + std::to_string(v) + " link is not a single cycle/path");
      ++r.num_nonmanifold_vertices;
      continue;
    }
    // Walk the chain from an end (or anywhere for a cycle) and count the edges reached.
    std::uint32_t start = edges[0].first;
    for (const auto& [w, d] : degree) {
      if (d == 1) start = w;
    }
    std::vector<bool> used(edges.size(), false);
    std::uint32_t current = start;
    std::size_t reached = 0;
    for (;;) {
      std::size_t next = edges.size();
      for (std::size_t i : at[current]) {
        if (!used[i]) {
          next = i;
          break;
        }
      }
      if (next == edges.size()) break;
      used[next] = true;
      ++reached;
      current = edges[next].first == current ? edges[next].second : edges[next].first;
    }
    if (reached != edges.size()) {
      Add(&r, "vertex " + std::to_string(v) + " link has several components");
      ++r.num_nonmanifold_vertices;
    }
  }
  return r;
}

}  // namespace semap::test
