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
// RANSAC counts a hypothesis's inliers this many points at a time between its early-drop checks.
constexpr size_t kRansacChunk = 256;
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

Plane Plane::FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  Plane p;
  p.normal = normal.normalized();
  p.offset = -p.normal.dot(point);
  // Any unit vector not parallel to n gives the in-plane frame.
  const Eigen::Vector3d helper =
      std::abs(p.normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  p.u = p.normal.cross(helper).normalized();
  p.v = p.normal.cross(p.u);
  return p;
}

PcaResult Pca(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& neighbours) {
  PcaResult r;
  if (neighbours.size() < 3) return r;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto i : neighbours) mean += points[i];
  mean /= static_cast<double>(neighbours.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto i : neighbours) {
    const Eigen::Vector3d d = points[i] - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = lambda.sum();
  r.normal = eig.eigenvectors().col(0);
  r.surface_variation = sum > 0.0 ? lambda(0) / sum : 0.0;
  r.valid = true;
  return r;
}

int RansacIterationsNeeded(double inlier_share, double confidence, int max_iterations) {
  if (confidence >= 1.0 || !(inlier_share > 0.0)) return max_iterations;
  const double all_inliers = std::pow(std::min(inlier_share, 1.0), 3);
  if (all_inliers >= 1.0) return std::min(1, max_iterations);
  const double needed = std::ceil(std::log(1.0 - confidence) / std::log(1.0 - all_inliers));
  return static_cast<int>(std::clamp(needed, 1.0, static_cast<double>(max_iterations)));
}

std::optional<Plane> FitPlaneRansac(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::uint32_t>& indices, double threshold_m,
                                    int iterations, int max_points, double confidence, std::mt19937_64& rng) {
  if (indices.size() < 3) return std::nullopt;
  // The evaluation sample: every member, or max_points of them drawn without replacement.
  std::vector<std::uint32_t> sample = indices;
  if (sample.size() > static_cast<size_t>(max_points)) {
    for (size_t i = 0; i < static_cast<size_t>(max_points); ++i) {
      std::uniform_int_distribution<size_t> pick(i, sample.size() - 1);
      std::swap(sample[i], sample[pick(rng)]);
    }
    sample.resize(static_cast<size_t>(max_points));
  }
  std::uniform_int_distribution<size_t> pick(0, sample.size() - 1);
  // The sample's coordinates, one array per axis: the counting loop below then reads them in order (and the
  // compiler can vectorise it) instead of gathering the points through their indices. The distance is
  // computed in the order SignedDistance computes it, n·x + offset.
  std::vector<double> xs(sample.size()), ys(sample.size()), zs(sample.size());
  for (size_t k = 0; k < sample.size(); ++k) {
    const Eigen::Vector3d& p = points[sample[k]];
    xs[k] = p.x();
    ys[k] = p.y();
    zs[k] = p.z();
  }
  std::optional<Plane> best;
  size_t best_inliers = 0;
  int needed = iterations;  // lowered as better hypotheses are found (adaptive stop)
  for (int it = 0; it < needed; ++it) {
    const Eigen::Vector3d& a = points[sample[pick(rng)]];
    const Eigen::Vector3d& b = points[sample[pick(rng)]];
    const Eigen::Vector3d& c = points[sample[pick(rng)]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    const Plane h = Plane::FromPointNormal(a, n);
    // Counted in chunks; a hypothesis that can no longer beat the best (inliers + points left ≤ best) is
    // dropped early: the same choice as counting every point.
    size_t inliers = 0;
    for (size_t begin = 0; begin < sample.size(); begin += kRansacChunk) {
      const size_t end = std::min(sample.size(), begin + kRansacChunk);
      const double nx = h.normal.x(), ny = h.normal.y(), nz = h.normal.z(), offset = h.offset;
      for (size_t k = begin; k < end; ++k) {
        inliers += std::abs(nx * xs[k] + ny * ys[k] + nz * zs[k] + offset) <= threshold_m ? 1 : 0;
      }
      if (inliers + (sample.size() - end) <= best_inliers) break;
    }
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = h;
      needed = RansacIterationsNeeded(static_cast<double>(inliers) / static_cast<double>(sample.size()),
                                      confidence, iterations);
    }
  }
  if (!best) return std::nullopt;
  // Least-squares refits (PCA) on the inliers among all the points: first of the best hypothesis, then of
  // that refit (so that any of the near-equal hypotheses an early stop may keep ends on the same plane).
  constexpr int kRefits = 2;
  Plane plane = *best;
  std::vector<std::uint32_t> inliers;
  for (int refit = 0; refit < kRefits; ++refit) {
    inliers.clear();
    for (auto i : indices) {
      if (std::abs(plane.SignedDistance(points[i])) <= threshold_m) inliers.push_back(i);
    }
    const PcaResult pca = Pca(points, inliers);
    if (!pca.valid) break;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (auto i : inliers) centroid += points[i];
    centroid /= static_cast<double>(inliers.size());
    plane = Plane::FromPointNormal(centroid, pca.normal);
  }
  return plane;
}

}  // namespace semap::simplify
