#include "engine/simplify/internal/linear_svm.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

std::optional<LinearSvm> TrainLinearSvm(const std::vector<Eigen::Vector2d>& x,
                                        const std::vector<int>& positive, const LinearSvmOptions& options) {
  const int n = static_cast<int>(x.size());
  if (n < 2 || positive.size() != x.size()) return std::nullopt;
  // Linear kernel: with z_t = y_t x_t and w = Σ α_t z_t, the dual gradient G = Qα − e is G_t = z_t·w − 1, so
  // it is read from w (two products) instead of kept per point. α = 0 at start.
  std::vector<double> y(n), alpha(n, 0.0), qd(n);
  std::vector<Eigen::Vector2d> z(n);
  int n_pos = 0;
  for (int t = 0; t < n; ++t) {
    y[t] = positive[t] ? 1.0 : -1.0;
    n_pos += positive[t] ? 1 : 0;
    z[t] = y[t] * x[t];
    qd[t] = x[t].squaredNorm();
  }
  if (n_pos == 0 || n_pos == n) return std::nullopt;
  const double c = options.c;
  Eigen::Vector2d w = Eigen::Vector2d::Zero();
  auto grad = [&](int t) { return z[t].dot(w) - 1.0; };

  // The points the scans visit, ascending (shrinking leaves out points at a bound that cannot be picked;
  // the end is always judged on all of them). The gradient is read from w, so nothing is reconstructed.
  std::vector<int> active(n);
  for (int t = 0; t < n; ++t) active[t] = t;
  const auto all_active = [&]() {
    active.resize(n);
    for (int t = 0; t < n; ++t) active[t] = t;
  };
  int counter = std::min(n, kShrinkEvery);
  bool unshrunk = false;
  // libsvm's be_shrunk: a point at a bound whose gradient keeps it out of both candidate sets' extremes.
  const auto shrink = [&](double g_max1, double g_max2) {
    std::size_t kept = 0;
    for (const int t : active) {
      const double g = grad(t);
      bool out = false;
      if (alpha[t] >= c) {
        out = y[t] > 0.0 ? -g > g_max1 : -g > g_max2;
      } else if (alpha[t] <= 0.0) {
        out = y[t] > 0.0 ? g > g_max2 : g > g_max1;
      }
      if (!out) active[kept++] = t;
    }
    active.resize(kept);
  };
  const auto extremes = [&](double* g_max1, double* g_max2) {
    *g_max1 = -std::numeric_limits<double>::infinity();
    *g_max2 = -std::numeric_limits<double>::infinity();
    for (const int t : active) {
      const double g = grad(t);
      if (y[t] > 0.0) {
        if (alpha[t] < c) *g_max1 = std::max(*g_max1, -g);
        if (alpha[t] > 0.0) *g_max2 = std::max(*g_max2, g);
      } else {
        if (alpha[t] > 0.0) *g_max1 = std::max(*g_max1, g);
        if (alpha[t] < c) *g_max2 = std::max(*g_max2, -g);
      }
    }
  };

  LinearSvm svm;
  for (; svm.iterations < options.max_iterations; ++svm.iterations) {
    if (--counter == 0) {
      counter = std::min(n, kShrinkEvery);
      double g_max1 = 0.0, g_max2 = 0.0;
      extremes(&g_max1, &g_max2);
      if (!unshrunk && g_max1 + g_max2 <= options.epsilon * kUnshrinkFactor) {
        unshrunk = true;
        all_active();
        extremes(&g_max1, &g_max2);
      }
      shrink(g_max1, g_max2);
    }
    // Working set (libsvm WSS 2): i maximises −y_t G_t over I_up = {α_t < C, y_t = +1} ∪ {α_t > 0, y_t = −1};
    // j minimises the second-order gain −b²/a over I_low with b = −y_i G_i + y_t G_t > 0, a = |x_i − x_t|².
    double g_max = -std::numeric_limits<double>::infinity();
    int i = -1;
    for (const int t : active) {
      const bool up = y[t] > 0.0 ? alpha[t] < c : alpha[t] > 0.0;
      if (!up) continue;
      const double v = -y[t] * grad(t);
      if (v >= g_max) {
        g_max = v;
        i = t;
      }
    }
    if (i < 0) break;
    double g_max2 = -std::numeric_limits<double>::infinity();
    double best_gain = std::numeric_limits<double>::infinity();
    int j = -1;
    for (const int t : active) {
      const bool low = y[t] > 0.0 ? alpha[t] > 0.0 : alpha[t] < c;
      if (!low) continue;
      const double v = y[t] * grad(t);  // −(−y_t G_t)
      g_max2 = std::max(g_max2, v);
      const double grad_diff = g_max + v;
      if (grad_diff > 0.0) {
        const double quad = qd[i] + qd[t] - 2.0 * x[i].dot(x[t]);
        const double gain = -(grad_diff * grad_diff) / (quad > 0.0 ? quad : kTau);
        if (gain <= best_gain) {
          j = t;
          best_gain = gain;
        }
      }
    }
    if (g_max + g_max2 < options.epsilon || j < 0) {
      // Optimal on the active points: the next pass judges it on all of them (and goes on if they are not).
      if (static_cast<int>(active.size()) == n) break;
      all_active();
      counter = std::min(n, kShrinkEvery);
      continue;  // counts as an iteration: the loop stays bounded by max_iterations
    }

    // The pair's analytic update, clipped to the box [0, C] (libsvm's Solver::Solve).
    const double old_i = alpha[i], old_j = alpha[j];
    const double g_i = grad(i), g_j = grad(j);
    const double qij = z[i].dot(z[j]);
    if (y[i] != y[j]) {
      double quad = qd[i] + qd[j] + 2.0 * qij;
      if (quad <= 0.0) quad = kTau;
      const double delta = (-g_i - g_j) / quad;
      const double diff = alpha[i] - alpha[j];
      alpha[i] += delta;
      alpha[j] += delta;
      if (diff > 0.0) {
        if (alpha[j] < 0.0) {
          alpha[j] = 0.0;
          alpha[i] = diff;
        }
      } else if (alpha[i] < 0.0) {
        alpha[i] = 0.0;
        alpha[j] = -diff;
      }
      if (diff > 0.0) {
        if (alpha[i] > c) {
          alpha[i] = c;
          alpha[j] = c - diff;
        }
      } else if (alpha[j] > c) {
        alpha[j] = c;
        alpha[i] = c + diff;
      }
    } else {
      double quad = qd[i] + qd[j] - 2.0 * qij;
      if (quad <= 0.0) quad = kTau;
      const double delta = (g_i - g_j) / quad;
      const double sum = alpha[i] + alpha[j];
      alpha[i] -= delta;
      alpha[j] += delta;
      if (sum > c) {
        if (alpha[i] > c) {
          alpha[i] = c;
          alpha[j] = sum - c;
        }
      } else if (alpha[j] < 0.0) {
        alpha[j] = 0.0;
        alpha[i] = sum;
      }
      if (sum > c) {
        if (alpha[j] > c) {
          alpha[j] = c;
          alpha[i] = sum - c;
        }
      } else if (alpha[i] < 0.0) {
        alpha[i] = 0.0;
        alpha[j] = sum;
      }
    }
    w += (alpha[i] - old_i) * z[i] + (alpha[j] - old_j) * z[j];
  }

  // ρ: the mean of y_t G_t over the free support vectors, else the middle of the feasible interval.
  double ub = std::numeric_limits<double>::infinity(), lb = -ub, sum_free = 0.0;
  int n_free = 0;
  for (int t = 0; t < n; ++t) {
    const double yg = y[t] * grad(t);
    const bool at_upper = alpha[t] >= c, at_lower = alpha[t] <= 0.0;
    if (at_upper || at_lower) {
      // At a bound: an upper bound on ρ when (upper, y = −1) or (lower, y = +1), else a lower bound.
      if (at_upper == (y[t] < 0.0)) {
        ub = std::min(ub, yg);
      } else {
        lb = std::max(lb, yg);
      }
    } else {
      ++n_free;
      sum_free += yg;
    }
  }
  svm.rho = n_free > 0 ? sum_free / n_free : 0.5 * (ub + lb);
  svm.w = w;
  return svm;
}

}  // namespace semap::simplify
