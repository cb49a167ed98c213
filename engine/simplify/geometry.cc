#include "engine/simplify/internal/geometry.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <numeric>

#include "engine/core/check.h"

namespace semap::simplify {

namespace {
struct VectorAdaptor {
  const std::vector<Eigen::Vector3d>* points;
  size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, VectorAdaptor>,
                                                 VectorAdaptor, 3, std::uint32_t>;
constexpr size_t kLeafSize = 16;
}  // namespace

struct PointIndex::Impl {
  explicit Impl(const std::vector<Eigen::Vector3d>& points)
      : adaptor{&points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)) {}
  VectorAdaptor adaptor;
  Tree tree;
};

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points) : impl_(std::make_unique<Impl>(points)) {}
PointIndex::~PointIndex() = default;

void PointIndex::Radius(const Eigen::Vector3d& query, double radius_m,
                        std::vector<std::uint32_t>* out) const {
  out->clear();
  if (impl_->adaptor.points->empty()) return;
  thread_local std::vector<std::pair<std::uint32_t, double>> matches;
  matches.clear();
  nanoflann::SearchParams params;
  params.sorted = false;
  impl_->tree.radiusSearch(query.data(), radius_m * radius_m, matches, params);
  out->reserve(matches.size());
  for (const auto& m : matches) out->push_back(m.first);
}

void PointIndex::Knn(const Eigen::Vector3d& query, int k, std::vector<std::uint32_t>* out) const {
  const size_t n = std::min<size_t>(static_cast<size_t>(std::max(k, 0)), impl_->adaptor.points->size());
  out->resize(n);
  if (n == 0) return;
  thread_local std::vector<double> dists;
  dists.resize(n);
  const size_t found = impl_->tree.knnSearch(query.data(), n, out->data(), dists.data());
  out->resize(found);
}

namespace {
// Cell coordinates are packed 21 bits per axis (wrapping): cells 2²¹ apart share a key, which only adds
// points that the distance test then drops.
constexpr int kCellBits = 21;
constexpr std::uint64_t kCellMask = (std::uint64_t{1} << kCellBits) - 1;
// Keys use 63 bits: this one is never a cell's.
constexpr std::uint64_t kEmptyKey = ~std::uint64_t{0};
// Fibonacci hashing of a key to a slot (the top slot_bits_ bits of key · 2⁶⁴/φ).
constexpr std::uint64_t kHashMultiplier = 0x9E3779B97F4A7C15ULL;

// The first slot of `key` in an open-addressing table of 2^bits slots.
std::size_t HomeSlot(std::uint64_t key, int bits) {
  return static_cast<std::size_t>((key * kHashMultiplier) >> (64 - bits));
}
}  // namespace

RadiusGrid::RadiusGrid(const std::vector<Eigen::Vector3d>& points, double radius_m)
    : points_(&points), radius_m_(radius_m) {
  SEMAP_ASSERT(radius_m > 0.0, "radius " << radius_m);
  const std::size_t n = points.size();
  // Points bucketed by cell without sorting: a first table (sized for one cell per point) counts the points
  // of each cell, a prefix sum gives each cell its range of order_, and the points are placed in ascending
  // index order, so each cell's range is ascending. Then the occupied cells move to a table sized for them.
  int count_bits = 1;
  while ((std::size_t{1} << count_bits) < 2 * std::max<std::size_t>(n, 1)) ++count_bits;
  std::vector<Slot> counting(std::size_t{1} << count_bits, Slot{kEmptyKey, 0, 0});
  const std::size_t count_mask = counting.size() - 1;
  std::vector<std::uint32_t> slot_of(n);
  std::vector<std::uint32_t> occupied;  // the counting table's occupied slots, in the order first seen
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = points[i];
    const std::uint64_t key = Key(CellOf(p.x()), CellOf(p.y()), CellOf(p.z()));
    std::size_t s = HomeSlot(key, count_bits);
    while (counting[s].key != kEmptyKey && counting[s].key != key) s = (s + 1) & count_mask;
    if (counting[s].key == kEmptyKey) {
      counting[s].key = key;
      occupied.push_back(static_cast<std::uint32_t>(s));
    }
    ++counting[s].end;  // the cell's count, for now
    slot_of[i] = static_cast<std::uint32_t>(s);
  }
  std::uint32_t next = 0;
  for (const std::uint32_t s : occupied) {
    Slot& slot = counting[s];
    slot.begin = next;
    next += slot.end;
    slot.end = slot.begin;  // the cell's write cursor
  }
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) order_[counting[slot_of[i]].end++] = static_cast<std::uint32_t>(i);
  slot_bits_ = 1;
  while ((std::size_t{1} << slot_bits_) < 2 * occupied.size()) ++slot_bits_;
  slots_.assign(std::size_t{1} << slot_bits_, Slot{kEmptyKey, 0, 0});
  const std::size_t mask = slots_.size() - 1;
  for (const std::uint32_t c : occupied) {
    const Slot& slot = counting[c];
    std::size_t s = Home(slot.key);
    while (slots_[s].key != kEmptyKey) s = (s + 1) & mask;
    slots_[s] = slot;
  }
}

std::int64_t RadiusGrid::CellOf(double coordinate) const {
  return static_cast<std::int64_t>(std::floor(coordinate / radius_m_));
}

std::uint64_t RadiusGrid::Key(std::int64_t x, std::int64_t y, std::int64_t z) const {
  return ((static_cast<std::uint64_t>(x) & kCellMask) << (2 * kCellBits)) |
         ((static_cast<std::uint64_t>(y) & kCellMask) << kCellBits) |
         (static_cast<std::uint64_t>(z) & kCellMask);
}

std::size_t RadiusGrid::Home(std::uint64_t key) const { return HomeSlot(key, slot_bits_); }

void RadiusGrid::Radius(const Eigen::Vector3d& query, std::vector<std::uint32_t>* out) const {
  out->clear();
  const double r2 = radius_m_ * radius_m_;
  const std::size_t mask = slots_.size() - 1;
  const std::int64_t cx = CellOf(query.x()), cy = CellOf(query.y()), cz = CellOf(query.z());
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const std::uint64_t key = Key(cx + dx, cy + dy, cz + dz);
        std::size_t s = Home(key);
        while (slots_[s].key != kEmptyKey && slots_[s].key != key) s = (s + 1) & mask;
        if (slots_[s].key != key) continue;
        for (std::uint32_t k = slots_[s].begin; k < slots_[s].end; ++k) {
          const std::uint32_t i = order_[k];
          if (((*points_)[i] - query).squaredNorm() <= r2) out->push_back(i);
        }
      }
    }
  }
}

}  // namespace semap::simplify
