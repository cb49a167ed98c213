#include "engine/sim/internal/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "engine/core/check.h"

namespace semap::sim::sim_internal {

SceneBuilder::SceneBuilder(Scene* scene) : scene_(scene) { SEMAP_ASSERT(scene != nullptr); }

std::uint32_t SceneBuilder::AddVertex(const Eigen::Vector3d& p) {
  scene_->vertices.push_back(p);
  return static_cast<std::uint32_t>(scene_->vertices.size() - 1);
}

void SceneBuilder::AddTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const Surface& s) {
  const auto& v = scene_->vertices;
  const Eigen::Vector3d n = (v[b] - v[a]).cross(v[c] - v[a]);
  const double len = n.norm();
  if (!(len > 1e-12)) return;  // degenerate: skip
  scene_->triangles.push_back({a, b, c});
  scene_->normals.push_back((n / len).cast<float>());
  scene_->labels.push_back(s.label);
  scene_->materials.push_back(s.material);
  scene_->object_ids.push_back(s.object_id);
}

void SceneBuilder::AddQuad(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                           const Eigen::Vector3d& p3, const Eigen::Vector3d& facing, const Surface& s) {
  const std::uint32_t a = AddVertex(p0), b = AddVertex(p1), c = AddVertex(p2), d = AddVertex(p3);
  const bool flip = (p1 - p0).cross(p2 - p0).dot(facing) < 0.0;
  if (flip) {
    AddTriangle(a, c, b, s);
    AddTriangle(a, d, c, s);
  } else {
    AddTriangle(a, b, c, s);
    AddTriangle(a, c, d, s);
  }
}

void SceneBuilder::AddBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double yaw,
                          const Surface& s, bool with_bottom) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  auto corner = [&](int i) {
    const Eigen::Vector3d l((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                            (i & 4) ? half.z() : -half.z());
    return Eigen::Vector3d(center + r * l);
  };
  const Eigen::Vector3d ex = r.col(0), ey = r.col(1), ez = r.col(2);
  AddQuad(corner(1), corner(3), corner(7), corner(5), ex, s);   // +x
  AddQuad(corner(0), corner(4), corner(6), corner(2), -ex, s);  // -x
  AddQuad(corner(2), corner(6), corner(7), corner(3), ey, s);   // +y
  AddQuad(corner(0), corner(1), corner(5), corner(4), -ey, s);  // -y
  AddQuad(corner(4), corner(5), corner(7), corner(6), ez, s);   // top
  if (with_bottom) AddQuad(corner(0), corner(2), corner(3), corner(1), -ez, s);
}

void SceneBuilder::AddCylinder(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius,
                               double length, int sides, const Surface& s) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d u = a.unitOrthogonal(), w = a.cross(u);
  const Eigen::Vector3d top = base + length * a;
  std::vector<std::uint32_t> bottom_ring, top_ring;
  for (int k = 0; k < sides; ++k) {
    const double ang = 2.0 * M_PI * k / sides;
    const Eigen::Vector3d d = radius * (std::cos(ang) * u + std::sin(ang) * w);
    bottom_ring.push_back(AddVertex(base + d));
    top_ring.push_back(AddVertex(top + d));
  }
  const std::uint32_t cb = AddVertex(base), ct = AddVertex(top);
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    AddTriangle(bottom_ring[k], bottom_ring[k1], top_ring[k1], s);
    AddTriangle(bottom_ring[k], top_ring[k1], top_ring[k], s);
    AddTriangle(ct, top_ring[k], top_ring[k1], s);
    AddTriangle(cb, bottom_ring[k1], bottom_ring[k], s);
  }
}

const std::pair<std::vector<Eigen::Vector3d>, std::vector<std::array<std::uint32_t, 3>>>&
SceneBuilder::Icosphere(int level) {
  SEMAP_ASSERT(level >= 0 && level <= 5);
  if (spheres_.empty()) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                      {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                      {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p.normalize();
    std::vector<std::array<std::uint32_t, 3>> f = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    spheres_.emplace_back(std::move(v), std::move(f));
  }
  while (static_cast<int>(spheres_.size()) <= level) {
    auto v = spheres_.back().first;
    const auto& f_in = spheres_.back().second;
    std::vector<std::array<std::uint32_t, 3>> f;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const auto idx = static_cast<std::uint32_t>(v.size() - 1);
      mid.emplace(key, idx);
      return idx;
    };
    for (const auto& tri : f_in) {
      const std::uint32_t ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]),
                          ca = midpoint(tri[2], tri[0]);
      f.push_back({tri[0], ab, ca});
      f.push_back({tri[1], bc, ab});
      f.push_back({tri[2], ca, bc});
      f.push_back({ab, bc, ca});
    }
    spheres_.emplace_back(std::move(v), std::move(f));
  }
  return spheres_[level];
}

void SceneBuilder::AddBlob(const Eigen::Vector3d& center, const Eigen::Vector3d& radii, int subdivisions,
                           double roughness, std::uint64_t seed, const Surface& s) {
  const auto& [dirs, faces] = Icosphere(subdivisions);
  const auto base = static_cast<std::uint32_t>(scene_->vertices.size());
  for (const auto& d : dirs) {
    // Two octaves of lumps plus a per-vertex jitter: irregular, leafy silhouettes.
    const double lumps = ValueNoise(d.x() * 1.7 + 11.0, d.y() * 1.7, d.z() * 1.7, seed) - 0.5;
    const double fine = ValueNoise(d.x() * 5.0, d.y() * 5.0 + 7.0, d.z() * 5.0, seed + 1) - 0.5;
    const double jitter = ValueNoise(d.x() * 23.0, d.y() * 23.0, d.z() * 23.0 + 3.0, seed + 2) - 0.5;
    const double f = 1.0 + roughness * (1.4 * lumps + 0.8 * fine + 0.5 * jitter);
    AddVertex(center + f * radii.cwiseProduct(d));
  }
  for (const auto& t : faces) AddTriangle(base + t[0], base + t[1], base + t[2], s);
}

void SceneBuilder::AddRoundedBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double yaw,
                                 double exponent, int subdivisions, const Surface& s) {
  const auto& [dirs, faces] = Icosphere(subdivisions);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto base = static_cast<std::uint32_t>(scene_->vertices.size());
  for (const auto& d : dirs) {
    const double sum = std::pow(std::abs(d.x() / half.x()), exponent) +
                       std::pow(std::abs(d.y() / half.y()), exponent) +
                       std::pow(std::abs(d.z() / half.z()), exponent);
    const double rad = std::pow(sum, -1.0 / exponent);
    AddVertex(center + r * (rad * d));
  }
  for (const auto& t : faces) AddTriangle(base + t[0], base + t[1], base + t[2], s);
}

// Sorts the triangles into square cells of the ground plane (stable: deterministic) and fills scene.chunks.
void SortIntoChunks(Scene* scene, double chunk_size_m) {
  SEMAP_ASSERT(chunk_size_m > 0.0);
  Scene& s = *scene;
  const size_t n = s.triangles.size();
  std::vector<std::pair<std::int64_t, std::int64_t>> key(n);
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3d c =
        (s.vertices[s.triangles[t][0]] + s.vertices[s.triangles[t][1]] + s.vertices[s.triangles[t][2]]) / 3.0;
    key[t] = {static_cast<std::int64_t>(std::floor(c.x() / chunk_size_m)),
              static_cast<std::int64_t>(std::floor(c.y() / chunk_size_m))};
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  auto permute = [&](auto& v) {
    auto copy = v;
    for (size_t k = 0; k < n; ++k) v[k] = copy[order[k]];
  };
  permute(s.triangles);
  permute(s.normals);
  permute(s.labels);
  permute(s.materials);
  permute(s.object_ids);
  std::vector<std::pair<std::int64_t, std::int64_t>> sorted_key(n);
  for (size_t k = 0; k < n; ++k) sorted_key[k] = key[order[k]];
  s.chunks.clear();
  for (size_t k = 0; k < n; ++k) {
    if (k == 0 || sorted_key[k] != sorted_key[k - 1])
      s.chunks.push_back({Eigen::AlignedBox3d(), static_cast<std::uint32_t>(k), 0});
    SceneChunk& c = s.chunks.back();
    ++c.count;
    for (int v = 0; v < 3; ++v) c.box.extend(s.vertices[s.triangles[k][v]]);
  }
}

}  // namespace semap::sim::sim_internal
