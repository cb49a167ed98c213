#include "engine/map/internal/steiner_lattice.h"

#include <cmath>

#include "engine/core/check.h"

namespace semap::map_internal {
namespace {

constexpr int kAxisBits = 21;
constexpr std::int64_t kAxisOffset = std::int64_t(1) << (kAxisBits - 1);
constexpr std::int64_t kAxisMask = (std::int64_t(1) << kAxisBits) - 1;
constexpr double kJitterFraction = 0.1;  // of the spacing, per axis

LatticeKey Pack(std::int64_t i, std::int64_t j, std::int64_t k) {
  return ((i + kAxisOffset) << (2 * kAxisBits)) | ((j + kAxisOffset) << kAxisBits) | (k + kAxisOffset);
}

Eigen::Array3i Unpack(LatticeKey key) {
  return {int(((key >> (2 * kAxisBits)) & kAxisMask) - kAxisOffset),
          int(((key >> kAxisBits) & kAxisMask) - kAxisOffset), int((key & kAxisMask) - kAxisOffset)};
}

std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

template <typename Fn>
void ForNodesAround(LatticeKey cube, int margin, Fn&& fn) {
  const Eigen::Array3i c = Unpack(cube);
  for (int i = c.x() - margin; i <= c.x() + 1 + margin; ++i)
    for (int j = c.y() - margin; j <= c.y() + 1 + margin; ++j)
      for (int k = c.z() - margin; k <= c.z() + 1 + margin; ++k) fn(Pack(i, j, k));
}

}  // namespace

SteinerLattice::SteinerLattice(double spacing_m, int margin_cubes)
    : spacing_m_(spacing_m), margin_(margin_cubes) {
  SEMAP_ASSERT(spacing_m > 0.0 && margin_cubes >= 1);
}

LatticeKey SteinerLattice::CubeOf(const Eigen::Vector3d& p) const {
  const double limit = double(kAxisOffset - 2 * margin_ - 2);
  const Eigen::Array3d c = (p / spacing_m_).array().floor();
  SEMAP_ASSERT((c.abs() < limit).all(), "point out of the lattice range: " << p.transpose());
  return Pack(std::int64_t(c.x()), std::int64_t(c.y()), std::int64_t(c.z()));
}

void SteinerLattice::Use(const Eigen::Vector3d& p, std::int64_t frame, std::vector<LatticeKey>* new_nodes) {
  const LatticeKey cube = CubeOf(p);
  auto [it, inserted] = cube_last_frame_.try_emplace(cube, frame);
  if (!inserted) {
    if (frame > it->second) it->second = frame;
    return;
  }
  ForNodesAround(cube, margin_, [&](LatticeKey node) {
    if (node_refs_[node]++ == 0) new_nodes->push_back(node);
  });
}

void SteinerLattice::Expire(std::int64_t oldest_frame, std::vector<LatticeKey>* released_nodes) {
  for (auto it = cube_last_frame_.begin(); it != cube_last_frame_.end();) {
    if (it->second >= oldest_frame) {
      ++it;
      continue;
    }
    ForNodesAround(it->first, margin_, [&](LatticeKey node) {
      auto n = node_refs_.find(node);
      SEMAP_ASSERT(n != node_refs_.end());
      if (--n->second == 0) {
        node_refs_.erase(n);
        released_nodes->push_back(node);
      }
    });
    it = cube_last_frame_.erase(it);
  }
}

Eigen::Vector3d SteinerLattice::Position(LatticeKey node) const {
  const Eigen::Array3i idx = Unpack(node);
  Eigen::Vector3d p;
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t h = SplitMix64(std::uint64_t(node) * 3 + std::uint64_t(axis));
    const double unit = double(h >> 11) * 0x1.0p-53;  // [0, 1)
    p[axis] = spacing_m_ * (idx[axis] + kJitterFraction * (2.0 * unit - 1.0));
  }
  return p;
}

}  // namespace semap::map_internal
