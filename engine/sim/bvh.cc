#include "engine/sim/bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "engine/core/check.h"

namespace semap::sim {
namespace {

constexpr int kBins = 12;
constexpr std::uint32_t kMaxLeafSize = 4;
// Boxes are stored in float: pad them so rounding never loses a hit.
constexpr float kBoxPadM = 2e-3f;
// Traversal stack size; Build() falls back to median splits past kSahDepth so the tree stays shallower.
constexpr int kMaxDepth = 128;
constexpr int kSahDepth = 80;

// An axis-aligned box grown point by point. Plain float arithmetic rather than Eigen's expressions: Build()
// extends boxes a few times per triangle and tree level, and in a sanitized build (-O1, Eigen's expressions
// not inlined) that form took 60 % of a rendering test's time (perf; bench/results/checks.md, "Sanitizers:
// the passes before the last whole one").
struct Box {
  std::array<float, 3> lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                          std::numeric_limits<float>::max()};
  std::array<float, 3> hi{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                          -std::numeric_limits<float>::max()};
  void Extend(const Eigen::Vector3f& p) { Extend(p, p); }
  void Extend(const Box& b) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
  }
  void Extend(const Eigen::Vector3f& p_lo, const Eigen::Vector3f& p_hi) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p_lo[k]), hi[k] = std::max(hi[k], p_hi[k]);
  }
  float Area() const {
    if (lo[0] > hi[0]) return 0.0f;
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
  }
};

}  // namespace

TriangleBvh::TriangleBvh(const Scene& scene) {
  const auto n = static_cast<std::uint32_t>(scene.triangles.size());
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<Eigen::Vector3f> centroids(n);
  std::vector<std::array<Eigen::Vector3f, 2>> boxes(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const auto& tri = scene.triangles[t];
    Box b;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v = scene.vertices[tri[k]];
      b.Extend(v.cast<float>());
      c += v;
    }
    centroids[t] = (c / 3.0).cast<float>();
    boxes[t] = {Eigen::Vector3f(b.lo[0] - kBoxPadM, b.lo[1] - kBoxPadM, b.lo[2] - kBoxPadM),
                Eigen::Vector3f(b.hi[0] + kBoxPadM, b.hi[1] + kBoxPadM, b.hi[2] + kBoxPadM)};
  }
  nodes_.reserve(n > 0 ? 2 * n / kMaxLeafSize + 1 : 1);
  if (n > 0) Build(0, n, centroids, boxes, 0);
  tris_.resize(n);
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto& tri = scene.triangles[order_[k]];
    const Eigen::Vector3d& a = scene.vertices[tri[0]];
    tris_[k] = {a, scene.vertices[tri[1]] - a, scene.vertices[tri[2]] - a};
  }
}

std::uint32_t TriangleBvh::Build(std::uint32_t begin, std::uint32_t end,
                                 std::vector<Eigen::Vector3f>& centroids,
                                 std::vector<std::array<Eigen::Vector3f, 2>>& boxes, int depth) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Box bounds, cbounds;
  for (std::uint32_t k = begin; k < end; ++k) {
    const std::uint32_t t = order_[k];
    bounds.Extend(boxes[t][0], boxes[t][1]);
    cbounds.Extend(centroids[t]);
  }
  auto make_leaf = [&]() {
    Node& node = nodes_[index];
    node.lo = bounds.lo;
    node.hi = bounds.hi;
    node.first_or_right = begin;
    node.count = end - begin;
    return index;
  };
  const std::uint32_t count = end - begin;
  if (count <= kMaxLeafSize) return make_leaf();
  int axis = 0;
  const Eigen::Vector3f ext(cbounds.hi[0] - cbounds.lo[0], cbounds.hi[1] - cbounds.lo[1],
                            cbounds.hi[2] - cbounds.lo[2]);
  ext.maxCoeff(&axis);
  if (!(ext[axis] > 0.0f)) return make_leaf();  // all centroids coincide

  // Binned SAH on the widest centroid axis.
  Box bin_box[kBins];
  std::uint32_t bin_count[kBins] = {};
  const float scale = kBins / ext[axis];
  auto bin_of = [&](std::uint32_t t) {
    return std::min(kBins - 1, static_cast<int>((centroids[t][axis] - cbounds.lo[axis]) * scale));
  };
  for (std::uint32_t k = begin; k < end; ++k) {
    const std::uint32_t t = order_[k];
    const int b = bin_of(t);
    ++bin_count[b];
    bin_box[b].Extend(boxes[t][0], boxes[t][1]);
  }
  float best_cost = std::numeric_limits<float>::max();
  int best_split = -1;
  for (int s = 1; s < kBins; ++s) {
    Box l, r;
    std::uint32_t nl = 0, nr = 0;
    for (int b = 0; b < s; ++b) l.Extend(bin_box[b]), nl += bin_count[b];
    for (int b = s; b < kBins; ++b) r.Extend(bin_box[b]), nr += bin_count[b];
    if (nl == 0 || nr == 0) continue;
    const float cost = l.Area() * nl + r.Area() * nr;
    if (cost < best_cost) best_cost = cost, best_split = s;
  }
  std::uint32_t mid;
  if (best_split < 0 || depth > kSahDepth) {
    mid = begin + count / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centroids[a][axis] < centroids[b][axis] ||
                              (centroids[a][axis] == centroids[b][axis] && a < b);
                     });
  } else {
    const auto it = std::stable_partition(order_.begin() + begin, order_.begin() + end,
                                          [&](std::uint32_t t) { return bin_of(t) < best_split; });
    mid = static_cast<std::uint32_t>(it - order_.begin());
  }
  Build(begin, mid, centroids, boxes, depth + 1);
  const std::uint32_t right = Build(mid, end, centroids, boxes, depth + 1);
  Node& node = nodes_[index];
  node.lo = bounds.lo;
  node.hi = bounds.hi;
  node.first_or_right = right;
  node.count = 0;
  return index;
}

std::optional<RayHit> TriangleBvh::Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                             double t_min, double t_max) const {
  if (nodes_.empty()) return std::nullopt;
  const Eigen::Vector3d inv = dir.cwiseInverse();
  auto box_hit = [&](const Node& n, double best, double* t_enter) {
    double t0 = t_min, t1 = best;
    for (int a = 0; a < 3; ++a) {
      double ta = (n.lo[a] - origin[a]) * inv[a], tb = (n.hi[a] - origin[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      if (std::isnan(ta)) ta = -std::numeric_limits<double>::infinity();  // 0 * inf on a slab boundary
      if (std::isnan(tb)) tb = std::numeric_limits<double>::infinity();
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    *t_enter = t0;
    return t0 <= t1;
  };
  std::optional<RayHit> hit;
  double best = t_max;
  std::uint32_t stack[kMaxDepth * 2];
  int sp = 0;
  double t_enter;
  if (!box_hit(nodes_[0], best, &t_enter)) return std::nullopt;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (n.count > 0) {
      for (std::uint32_t k = n.first_or_right; k < n.first_or_right + n.count; ++k) {
        // Möller-Trumbore.
        const Tri& tri = tris_[k];
        const Eigen::Vector3d p = dir.cross(tri.e2);
        const double det = tri.e1.dot(p);
        if (std::abs(det) < 1e-18) continue;
        const double inv_det = 1.0 / det;
        const Eigen::Vector3d s = origin - tri.v0;
        const double u = s.dot(p) * inv_det;
        if (u < 0.0 || u > 1.0) continue;
        const Eigen::Vector3d q = s.cross(tri.e1);
        const double v = dir.dot(q) * inv_det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t = tri.e2.dot(q) * inv_det;
        if (t >= t_min && t <= best) {
          best = t;
          hit = RayHit{t, order_[k]};
        }
      }
      continue;
    }
    const std::uint32_t l = static_cast<std::uint32_t>(&n - nodes_.data()) + 1, r = n.first_or_right;
    double tl, tr;
    const bool hl = box_hit(nodes_[l], best, &tl), hr = box_hit(nodes_[r], best, &tr);
    SEMAP_ASSERT(sp + 2 <= kMaxDepth * 2, "BVH too deep");
    if (hl && hr) {
      if (tl < tr) {
        stack[sp++] = r;
        stack[sp++] = l;
      } else {
        stack[sp++] = l;
        stack[sp++] = r;
      }
    } else if (hl) {
      stack[sp++] = l;
    } else if (hr) {
      stack[sp++] = r;
    }
  }
  return hit;
}

}  // namespace semap::sim
