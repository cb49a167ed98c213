#include "engine/simplify/internal/linear_svm.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/simplify/internal/linear_svm_steps.h"

namespace semap::simplify {

namespace {
// libsvm's floor on a non-positive curvature of the pair's sub-problem.
constexpr double kTau = 1e-12;
// Shrinking (libsvm's): every this many pair updates (or n, if fewer) the points at a bound that no working
// set can pick are left out of the scans.
constexpr int kShrinkEvery = 1000;
// Once the violation on the active points falls below this multiple of epsilon, every point is scanned again
// (libsvm's unshrink), so that the end is judged on all of them.
constexpr double kUnshrinkFactor = 10.0;
}  // namespace

std::optional<SvmDual> MakeSvmDual(const std::vector<Eigen::Vector2d>& x, const std::vector<int>& positive,
                                   double c) {
  const int n = static_cast<int>(x.size());
  if (n < 2 || positive.size() != x.size()) return std::nullopt;
  SvmDual dual;
  dual.c = c;
  dual.x = x;
  dual.y.resize(n);
  dual.z.resize(n);
  dual.qd.resize(n);
  dual.alpha.assign(n, 0.0);
  int n_pos = 0;
  for (int t = 0; t < n; ++t) {
    dual.y[t] = positive[t] ? 1.0 : -1.0;
    n_pos += positive[t] ? 1 : 0;
    dual.z[t] = dual.y[t] * x[t];
    dual.qd[t] = x[t].squaredNorm();
  }
  if (n_pos == 0 || n_pos == n) return std::nullopt;
  return dual;
}

std::vector<int> AllPoints(int n) {
  std::vector<int> all(n);
  for (int t = 0; t < n; ++t) all[t] = t;
  return all;
}

SvmViolation MaxViolation(const SvmDual& dual, const std::vector<int>& active) {
  SvmViolation v{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const int t : active) {
    const double g = dual.Gradient(t);
    if (dual.y[t] > 0.0) {
      if (dual.alpha[t] < dual.c) v.g_max1 = std::max(v.g_max1, -g);
      if (dual.alpha[t] > 0.0) v.g_max2 = std::max(v.g_max2, g);
    } else {
      if (dual.alpha[t] > 0.0) v.g_max1 = std::max(v.g_max1, g);
      if (dual.alpha[t] < dual.c) v.g_max2 = std::max(v.g_max2, -g);
    }
  }
  return v;
}

void RemoveShrinkable(const SvmDual& dual, const SvmViolation& violation, std::vector<int>* active) {
  std::size_t kept = 0;
  for (const int t : *active) {
    const double g = dual.Gradient(t);
    bool out = false;
    if (dual.alpha[t] >= dual.c) {
      out = dual.y[t] > 0.0 ? -g > violation.g_max1 : -g > violation.g_max2;
    } else if (dual.alpha[t] <= 0.0) {
      out = dual.y[t] > 0.0 ? g > violation.g_max2 : g > violation.g_max1;
    }
    if (!out) (*active)[kept++] = t;
  }
  active->resize(kept);
}

void ShrinkActive(const SvmDual& dual, double unshrink_below, bool* unshrunk, std::vector<int>* active) {
  SvmViolation violation = MaxViolation(dual, *active);
  if (!*unshrunk && violation.g_max1 + violation.g_max2 <= unshrink_below) {
    *unshrunk = true;
    *active = AllPoints(dual.size());
    violation = MaxViolation(dual, *active);
  }
  RemoveShrinkable(dual, violation, active);
}

SvmWorkingSet SelectWorkingSet(const SvmDual& dual, const std::vector<int>& active, double tau) {
  SvmWorkingSet ws;
  ws.g_max = -std::numeric_limits<double>::infinity();
  for (const int t : active) {
    if (!dual.InUp(t)) continue;
    const double v = -dual.y[t] * dual.Gradient(t);
    if (v >= ws.g_max) {
      ws.g_max = v;
      ws.i = t;
    }
  }
  if (ws.i < 0) return ws;
  const int i = ws.i;
  ws.g_max2 = -std::numeric_limits<double>::infinity();
  double best_gain = std::numeric_limits<double>::infinity();
  for (const int t : active) {
    if (!dual.InLow(t)) continue;
    const double v = dual.y[t] * dual.Gradient(t);  // −(−y_t G_t)
    ws.g_max2 = std::max(ws.g_max2, v);
    const double grad_diff = ws.g_max + v;
    if (grad_diff > 0.0) {
      const double quad = dual.qd[i] + dual.qd[t] - 2.0 * dual.x[i].dot(dual.x[t]);
      const double gain = -(grad_diff * grad_diff) / (quad > 0.0 ? quad : tau);
      if (gain <= best_gain) {
        ws.j = t;
        best_gain = gain;
      }
    }
  }
  return ws;
}

namespace {

// y_i ≠ y_j: α_i − α_j stays, both move by the same step, then are clipped back into the box.
SvmPair SolveOppositePair(SvmPair a, double g_i, double g_j, double quad, double c) {
  const double delta = (-g_i - g_j) / quad;
  const double diff = a.alpha_i - a.alpha_j;
  a.alpha_i += delta;
  a.alpha_j += delta;
  if (diff > 0.0) {
    if (a.alpha_j < 0.0) {
      a.alpha_j = 0.0;
      a.alpha_i = diff;
    }
  } else if (a.alpha_i < 0.0) {
    a.alpha_i = 0.0;
    a.alpha_j = -diff;
  }
  if (diff > 0.0) {
    if (a.alpha_i > c) {
      a.alpha_i = c;
      a.alpha_j = c - diff;
    }
  } else if (a.alpha_j > c) {
    a.alpha_j = c;
    a.alpha_i = c + diff;
  }
  return a;
}

// Clips a pair whose sum `sum` is fixed back into the box on one side: `a` down to c (when the sum exceeds
// c), else `b` up to 0.
void ClipPairWithSum(double sum, double c, double* a, double* b) {
  if (sum > c) {
    if (*a > c) {
      *a = c;
      *b = sum - c;
    }
  } else if (*b < 0.0) {
    *b = 0.0;
    *a = sum;
  }
}

// y_i = y_j: α_i + α_j stays, one moves up by the step the other moves down, then both are clipped.
SvmPair SolveSamePair(SvmPair a, double g_i, double g_j, double quad, double c) {
  const double delta = (g_i - g_j) / quad;
  const double sum = a.alpha_i + a.alpha_j;
  a.alpha_i -= delta;
  a.alpha_j += delta;
  ClipPairWithSum(sum, c, &a.alpha_i, &a.alpha_j);
  ClipPairWithSum(sum, c, &a.alpha_j, &a.alpha_i);
  return a;
}

}  // namespace

SvmPair SolvePair(const SvmPair& old, double g_i, double g_j, double q_ii, double q_jj, double q_ij,
                  bool same_label, double c, double tau) {
  double quad = same_label ? q_ii + q_jj - 2.0 * q_ij : q_ii + q_jj + 2.0 * q_ij;
  if (quad <= 0.0) quad = tau;
  return same_label ? SolveSamePair(old, g_i, g_j, quad, c) : SolveOppositePair(old, g_i, g_j, quad, c);
}

void UpdatePair(SvmDual* dual, int i, int j, double tau) {
  const SvmPair old{dual->alpha[i], dual->alpha[j]};
  const SvmPair next = SolvePair(old, dual->Gradient(i), dual->Gradient(j), dual->qd[i], dual->qd[j],
                                 dual->z[i].dot(dual->z[j]), dual->y[i] == dual->y[j], dual->c, tau);
  dual->alpha[i] = next.alpha_i;
  dual->alpha[j] = next.alpha_j;
  dual->w += (next.alpha_i - old.alpha_i) * dual->z[i] + (next.alpha_j - old.alpha_j) * dual->z[j];
}

double SvmRho(const SvmDual& dual) {
  double ub = std::numeric_limits<double>::infinity(), lb = -ub, sum_free = 0.0;
  int n_free = 0;
  for (int t = 0; t < dual.size(); ++t) {
    const double yg = dual.y[t] * dual.Gradient(t);
    const bool at_upper = dual.alpha[t] >= dual.c, at_lower = dual.alpha[t] <= 0.0;
    if (at_upper || at_lower) {
      // At a bound: an upper bound on ρ when (upper, y = −1) or (lower, y = +1), else a lower bound.
      if (at_upper == (dual.y[t] < 0.0)) {
        ub = std::min(ub, yg);
      } else {
        lb = std::max(lb, yg);
      }
    } else {
      ++n_free;
      sum_free += yg;
    }
  }
  return n_free > 0 ? sum_free / n_free : 0.5 * (ub + lb);
}

std::optional<LinearSvm> TrainLinearSvm(const std::vector<Eigen::Vector2d>& x,
                                        const std::vector<int>& positive, const LinearSvmOptions& options) {
  std::optional<SvmDual> dual = MakeSvmDual(x, positive, options.c);
  if (!dual) return std::nullopt;
  const int n = dual->size();
  // The points the scans visit, ascending (shrinking leaves out points at a bound that cannot be picked;
  // the end is always judged on all of them).
  std::vector<int> active = AllPoints(n);
  int counter = std::min(n, kShrinkEvery);
  bool unshrunk = false;
  LinearSvm svm;
  for (; svm.iterations < options.max_iterations; ++svm.iterations) {
    if (--counter == 0) {
      counter = std::min(n, kShrinkEvery);
      ShrinkActive(*dual, options.epsilon * kUnshrinkFactor, &unshrunk, &active);
    }
    const SvmWorkingSet ws = SelectWorkingSet(*dual, active, kTau);
    if (ws.i < 0) break;
    if (ws.g_max + ws.g_max2 < options.epsilon || ws.j < 0) {
      // Optimal on the active points: the next pass judges it on all of them (and goes on if they are not).
      if (static_cast<int>(active.size()) == n) break;
      active = AllPoints(n);
      counter = std::min(n, kShrinkEvery);
      continue;  // counts as an iteration: the loop stays bounded by max_iterations
    }
    UpdatePair(&*dual, ws.i, ws.j, kTau);
  }
  svm.rho = SvmRho(*dual);
  svm.w = dual->w;
  return svm;
}

}  // namespace semap::simplify
