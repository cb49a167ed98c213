// The steps of TrainLinearSvm's SMO solver (internal/linear_svm.h), each on its own. Not API.
//
// The dual: min ½ αᵀQα − Σ α_t over 0 ≤ α_t ≤ C with Σ y_t α_t = 0, where Q_st = y_s y_t x_s·x_t. With the
// linear kernel, z_t = y_t x_t and w = Σ α_t z_t, the gradient G = Qα − e is G_t = z_t·w − 1: it is read
// from w instead of kept per point.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace semap::simplify {

// The dual problem and SMO's current point on it.
struct SvmDual {
  double c = 0.0;                               // the box [0, C]
  std::vector<Eigen::Vector2d> x;               // the points
  std::vector<double> y;                        // their labels, +1 or −1
  std::vector<Eigen::Vector2d> z;               // y_t x_t
  std::vector<double> qd;                       // |x_t|²: Q's diagonal
  std::vector<double> alpha;                    // the dual variables
  Eigen::Vector2d w = Eigen::Vector2d::Zero();  // Σ α_t z_t

  int size() const { return static_cast<int>(x.size()); }
  // G_t = z_t·w − 1.
  double Gradient(int t) const { return z[t].dot(w) - 1.0; }
  // libsvm's I_up: α_t can grow along y_t (α_t < C for y_t = +1, α_t > 0 for y_t = −1).
  bool InUp(int t) const { return y[t] > 0.0 ? alpha[t] < c : alpha[t] > 0.0; }
  // libsvm's I_low: α_t can shrink along y_t.
  bool InLow(int t) const { return y[t] > 0.0 ? alpha[t] > 0.0 : alpha[t] < c; }
};

// The dual of `x` with labels `positive` (same size) at α = 0; nullopt with fewer than two points or one
// class only.
std::optional<SvmDual> MakeSvmDual(const std::vector<Eigen::Vector2d>& x, const std::vector<int>& positive,
                                   double c);

// 0, 1, ..., n − 1: every point active.
std::vector<int> AllPoints(int n);

// The largest violations over `active`: max −y_t G_t over I_up (g_max1) and max y_t G_t over I_low
// (g_max2); −∞ for an empty set. The problem is optimal to ε when g_max1 + g_max2 < ε.
struct SvmViolation {
  double g_max1 = 0.0;
  double g_max2 = 0.0;
};
SvmViolation MaxViolation(const SvmDual& dual, const std::vector<int>& active);

// Leaves out of `active` (order kept) the points at a bound whose gradient keeps them out of both extremes
// of `violation` (libsvm's be_shrunk): no working set can pick them while it holds.
void RemoveShrinkable(const SvmDual& dual, const SvmViolation& violation, std::vector<int>* active);

// libsvm's periodic shrinking: the violation on `active`; the first time it falls to unshrink_below, every
// point becomes active again (and *unshrunk true) and the violation is taken on all of them; then the
// shrinkable points leave.
void ShrinkActive(const SvmDual& dual, double unshrink_below, bool* unshrunk, std::vector<int>* active);

// libsvm's second-order working set (WSS 2) over `active`: i maximises −y_t G_t over I_up (the last of equal
// ones); j minimises the gain −b²/a over I_low with b = −y_i G_i + y_t G_t > 0 and a = |x_i − x_t|² (the
// last of equal ones, a ≤ 0 taken as tau). i = −1 when I_up is empty (then j is not sought); j = −1 when no
// point of I_low has b > 0. g_max = −y_i G_i, g_max2 = max y_t G_t over I_low.
struct SvmWorkingSet {
  int i = -1;
  int j = -1;
  double g_max = 0.0;
  double g_max2 = 0.0;
};
SvmWorkingSet SelectWorkingSet(const SvmDual& dual, const std::vector<int>& active, double tau);

// The pair's sub-problem solved and clipped to the box [0, c] as libsvm's Solver::Solve does: the new
// (α_i, α_j) from the old ones, their gradients g_i, g_j, and q_ij = z_i·z_j (Q_ij), with q_ii, q_jj the
// diagonal; `same_label` says y_i = y_j. A non-positive curvature is taken as tau.
struct SvmPair {
  double alpha_i = 0.0;
  double alpha_j = 0.0;
};
SvmPair SolvePair(const SvmPair& old, double g_i, double g_j, double q_ii, double q_jj, double q_ij,
                  bool same_label, double c, double tau);

// Applies SolvePair to points i and j of `dual` (their α and w).
void UpdatePair(SvmDual* dual, int i, int j, double tau);

// ρ as libsvm computes it: the mean of y_t G_t over the free support vectors (0 < α_t < C), else the middle
// of the interval the bounded ones leave.
double SvmRho(const SvmDual& dual);

}  // namespace semap::simplify
