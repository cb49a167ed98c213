#include "engine/map/internal/vote_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace semap::map_internal {
namespace {

// StandardNormalCdf's table: Φ and φ at x = −kNormalCdfLimit + i / kNormalCdfStepsPerUnit.
constexpr int kNormalCdfStepsPerUnit = 32;
constexpr int kNormalCdfNodes = static_cast<int>(2.0 * kNormalCdfLimit * kNormalCdfStepsPerUnit) + 1;

struct NormalCdfNode {
  double cdf;
  double density;  // dΦ/dx
};

const std::vector<NormalCdfNode>& NormalCdfTable() {
  static const std::vector<NormalCdfNode> table = [] {
    std::vector<NormalCdfNode> nodes(kNormalCdfNodes);
    const double inverse_sqrt_two_pi = 1.0 / std::sqrt(2.0 * M_PI);
    for (int i = 0; i < kNormalCdfNodes; ++i) {
      const double x = -kNormalCdfLimit + double(i) / kNormalCdfStepsPerUnit;
      nodes[i] = {0.5 * std::erfc(-x / std::sqrt(2.0)), inverse_sqrt_two_pi * std::exp(-0.5 * x * x)};
    }
    return nodes;
  }();
  return table;
}

}  // namespace

double StandardNormalCdf(double x) {
  if (!(x > -kNormalCdfLimit)) return 0.0;
  if (x >= kNormalCdfLimit) return 1.0;
  const std::vector<NormalCdfNode>& table = NormalCdfTable();
  const double s = (x + kNormalCdfLimit) * kNormalCdfStepsPerUnit;
  const int i = std::min(static_cast<int>(s), kNormalCdfNodes - 2);
  const double t = s - i, t2 = t * t, t3 = t2 * t;
  const double step = 1.0 / kNormalCdfStepsPerUnit;
  const NormalCdfNode& a = table[i];
  const NormalCdfNode& b = table[i + 1];
  const double value = (2.0 * t3 - 3.0 * t2 + 1.0) * a.cdf + (t3 - 2.0 * t2 + t) * step * a.density +
                       (3.0 * t2 - 2.0 * t3) * b.cdf + (t3 - t2) * step * b.density;
  return std::clamp(value, 0.0, 1.0);  // rounding at the table's ends
}

double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();  // vertex region a
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();  // vertex region b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (ap - ab * (d1 / (d1 - d3))).norm();  // edge ab
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.norm();  // vertex region c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (ap - ac * (d2 / (d2 - d6))).norm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge bc
    return (bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))).norm();
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) {  // degenerate (zero-area) triangle: closest of its edges
    return std::min({ap.norm(), bp.norm(), cp.norm()});
  }
  const double v = vb / denom, w = vc / denom;
  return (ap - ab * v - ac * w).norm();  // face region
}

double DistanceToClosestFacet(CellHandle cell, VertexHandle target, double saturation_m) {
  std::array<VertexHandle, 4> v{cell->vertex(0), cell->vertex(1), cell->vertex(2), cell->vertex(3)};
  const Eigen::Vector3d p = ToEigen(target->point());
  if (v[0] != target && v[1] != target && v[2] != target && v[3] != target) {
    Eigen::Vector3d lo = ToEigen(v[0]->point()), hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(ToEigen(v[k]->point()));
      hi = hi.cwiseMax(ToEigen(v[k]->point()));
    }
    const double box_distance = (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
    if (box_distance >= saturation_m) return box_distance;
  }
  std::sort(v.begin(), v.end(), [](VertexHandle x, VertexHandle y) {
    const Point &a = x->point(), &b = y->point();
    if (a.x() != b.x()) return a.x() < b.x();
    if (a.y() != b.y()) return a.y() < b.y();
    return a.z() < b.z();
  });
  double best = std::numeric_limits<double>::infinity();
  for (int skip = 0; skip < 4; ++skip) {
    std::array<Eigen::Vector3d, 3> tri;
    bool contains_target = false;
    for (int k = 0, n = 0; k < 4; ++k) {
      if (k == skip) continue;
      if (v[k] == target) contains_target = true;
      tri[n++] = ToEigen(v[k]->point());
    }
    if (contains_target) continue;
    best = std::min(best, PointTriangleDistance(p, tri[0], tri[1], tri[2]));
  }
  return best;
}

}  // namespace semap::map_internal
