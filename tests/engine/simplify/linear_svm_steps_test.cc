// The steps of TrainLinearSvm's solver (internal/linear_svm_steps.h), each against a reference computed
// another way: the dual's gradient from the explicit matrix Q, the pair's sub-problem by clamping its
// unconstrained minimum to the feasible segment and by a dense search along it.
#include "engine/simplify/internal/linear_svm_steps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace semap::simplify {
namespace {

constexpr double kTau = 1e-12;

// A dual of `n` random points in the unit square with random labels (both present) and α drawn in [0, c],
// a third of them at a bound; w made consistent with α.
SvmDual RandomDual(std::uint64_t seed, int n, double c) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector2d> x;
  std::vector<int> positive;
  for (int t = 0; t < n; ++t) {
    x.emplace_back(u(rng), u(rng));
    positive.push_back(t < 2 ? t : (u(rng) < 0.5 ? 1 : 0));
  }
  std::optional<SvmDual> dual = MakeSvmDual(x, positive, c);
  EXPECT_TRUE(dual.has_value());
  for (int t = 0; t < n; ++t) {
    const double r = u(rng);
    dual->alpha[t] = r < 0.15 ? 0.0 : r < 0.3 ? c : c * u(rng);
    dual->w += dual->alpha[t] * dual->z[t];
  }
  return *dual;
}

// G = Qα − e with Q_st = y_s y_t x_s·x_t written out.
std::vector<double> GradientFromQ(const SvmDual& d) {
  std::vector<double> g(d.size(), -1.0);
  for (int s = 0; s < d.size(); ++s) {
    for (int t = 0; t < d.size(); ++t) g[s] += d.y[s] * d.y[t] * d.x[s].dot(d.x[t]) * d.alpha[t];
  }
  return g;
}

TEST(LinearSvmSteps, TheDualStartsAtZeroWithTheLabelsSigns) {
  const auto dual = MakeSvmDual({{1.0, 2.0}, {-3.0, 0.5}, {0.0, -1.0}}, {1, 0, 1}, 4.0);
  ASSERT_TRUE(dual.has_value());
  EXPECT_EQ(dual->y, (std::vector<double>{1.0, -1.0, 1.0}));
  EXPECT_EQ(dual->z[1], Eigen::Vector2d(3.0, -0.5));
  EXPECT_EQ(dual->qd, (std::vector<double>{5.0, 9.25, 1.0}));
  EXPECT_EQ(dual->alpha, (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(dual->Gradient(0), -1.0);  // w = 0
  EXPECT_FALSE(MakeSvmDual({{0.0, 0.0}, {1.0, 1.0}}, {0, 0}, 1.0).has_value());
  EXPECT_FALSE(MakeSvmDual({{0.0, 0.0}, {1.0, 1.0}}, {1}, 1.0).has_value());
}

TEST(LinearSvmSteps, TheGradientReadFromWIsQAlphaMinusOne) {
  const SvmDual d = RandomDual(1, 40, 3.0);
  const std::vector<double> g = GradientFromQ(d);
  for (int t = 0; t < d.size(); ++t) EXPECT_NEAR(d.Gradient(t), g[t], 1e-9) << t;
}

TEST(LinearSvmSteps, MaxViolationAndWorkingSetAgreeWithAFullScan) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const SvmDual d = RandomDual(seed, 30, 2.0);
    const std::vector<double> g = GradientFromQ(d);
    std::vector<int> active = AllPoints(d.size());
    // The reference: I_up / I_low from the box and the labels, the violations from Q's gradient.
    double up_max = -std::numeric_limits<double>::infinity(), low_max = up_max;
    int i = -1;
    for (int t = 0; t < d.size(); ++t) {
      const bool up = (d.y[t] > 0 && d.alpha[t] < d.c) || (d.y[t] < 0 && d.alpha[t] > 0);
      const bool low = (d.y[t] > 0 && d.alpha[t] > 0) || (d.y[t] < 0 && d.alpha[t] < d.c);
      if (up && -d.y[t] * g[t] >= up_max) up_max = -d.y[t] * g[t], i = t;
      if (low) low_max = std::max(low_max, d.y[t] * g[t]);
    }
    const SvmViolation v = MaxViolation(d, active);
    EXPECT_NEAR(v.g_max1, up_max, 1e-9);
    EXPECT_NEAR(v.g_max2, low_max, 1e-9);
    // j: the largest second-order gain b² / a over I_low with b > 0.
    int j = -1;
    double best = 0.0;
    for (int t = 0; t < d.size(); ++t) {
      const bool low = (d.y[t] > 0 && d.alpha[t] > 0) || (d.y[t] < 0 && d.alpha[t] < d.c);
      const double b = -d.y[i] * g[i] + d.y[t] * g[t];
      if (!low || b <= 0.0) continue;
      const double a = std::max((d.x[i] - d.x[t]).squaredNorm(), kTau);
      if (b * b / a >= best) best = b * b / a, j = t;
    }
    const SvmWorkingSet ws = SelectWorkingSet(d, active, kTau);
    EXPECT_EQ(ws.i, i) << "seed " << seed;
    EXPECT_EQ(ws.j, j) << "seed " << seed;
    EXPECT_NEAR(ws.g_max, up_max, 1e-9);
    EXPECT_NEAR(ws.g_max2, low_max, 1e-9);
  }
}

TEST(LinearSvmSteps, AnEmptyUpSetHasNoWorkingSet) {
  // Every positive point at C and every negative one at 0: no α can move along its label upwards.
  auto d = MakeSvmDual({{0.0, 0.0}, {1.0, 0.0}}, {1, 0}, 1.0);
  ASSERT_TRUE(d.has_value());
  d->alpha = {1.0, 0.0};
  d->w = d->z[0];
  const SvmWorkingSet ws = SelectWorkingSet(*d, AllPoints(2), kTau);
  EXPECT_EQ(ws.i, -1);
  EXPECT_EQ(ws.j, -1);
}

// The pair's sub-problem: along the constraint y_i d_i + y_j d_j = 0 the dual changes by
// f(d) = (g_i ∓ g_j) d + ½ a d² for d_i = d, d_j = ∓d (same labels: −; opposite: +).
struct PairProblem {
  SvmPair old;
  double g_i, g_j, q_ii, q_jj, q_ij, c;
  bool same;
  double Sign() const { return same ? -1.0 : 1.0; }  // d_j = Sign() · d_i
  double Curvature() const { return std::max(q_ii + q_jj + 2.0 * Sign() * q_ij, kTau); }
  double F(double d) const { return (g_i + Sign() * g_j) * d + 0.5 * Curvature() * d * d; }
  // The feasible steps: 0 ≤ α_i + d ≤ c and 0 ≤ α_j + Sign() d ≤ c.
  double Low() const { return std::max(-old.alpha_i, same ? old.alpha_j - c : -old.alpha_j); }
  double High() const { return std::min(c - old.alpha_i, same ? old.alpha_j : c - old.alpha_j); }
};

TEST(LinearSvmSteps, ThePairUpdateIsTheClampedMinimumOfItsSubProblem) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    PairProblem p;
    p.c = 0.5 + 10.0 * u(rng);
    p.old = {p.c * u(rng), p.c * u(rng)};
    if (trial % 5 == 0) p.old.alpha_i = 0.0;
    if (trial % 7 == 0) p.old.alpha_j = p.c;
    const Eigen::Vector2d xi(u(rng), u(rng)), xj(u(rng), u(rng));
    p.same = trial % 2 == 0;
    p.q_ii = xi.squaredNorm();
    p.q_jj = xj.squaredNorm();
    p.q_ij = (p.same ? 1.0 : -1.0) * xi.dot(xj);
    p.g_i = 4.0 * (u(rng) - 0.5);
    p.g_j = 4.0 * (u(rng) - 0.5);
    const SvmPair got = SolvePair(p.old, p.g_i, p.g_j, p.q_ii, p.q_jj, p.q_ij, p.same, p.c, kTau);
    const double d = std::clamp(-(p.g_i + p.Sign() * p.g_j) / p.Curvature(), p.Low(), p.High());
    EXPECT_NEAR(got.alpha_i, p.old.alpha_i + d, 1e-9) << "trial " << trial;
    EXPECT_NEAR(got.alpha_j, p.old.alpha_j + p.Sign() * d, 1e-9) << "trial " << trial;
    // And no feasible step on a dense grid does better.
    const double f = p.F(got.alpha_i - p.old.alpha_i);
    for (int k = 0; k <= 200; ++k) {
      const double s = p.Low() + (p.High() - p.Low()) * k / 200.0;
      EXPECT_LE(f, p.F(s) + 1e-9) << "trial " << trial;
    }
  }
}

TEST(LinearSvmSteps, UpdatePairKeepsWTheSumOfAlphaZ) {
  SvmDual d = RandomDual(3, 20, 2.0);
  const SvmWorkingSet ws = SelectWorkingSet(d, AllPoints(d.size()), kTau);
  ASSERT_GE(ws.j, 0);
  const double balance = d.y[ws.i] * d.alpha[ws.i] + d.y[ws.j] * d.alpha[ws.j];
  UpdatePair(&d, ws.i, ws.j, kTau);
  Eigen::Vector2d w = Eigen::Vector2d::Zero();
  for (int t = 0; t < d.size(); ++t) w += d.alpha[t] * d.z[t];
  EXPECT_NEAR((d.w - w).norm(), 0.0, 1e-12);
  EXPECT_NEAR(d.y[ws.i] * d.alpha[ws.i] + d.y[ws.j] * d.alpha[ws.j], balance, 1e-12);  // Σ y α stays
}

TEST(LinearSvmSteps, ShrinkingLeavesOutOnlyBoundedPointsPastTheExtremes) {
  // Four points on the x axis, w = (1, 0): G_t = y_t x_t − 1.
  auto d = MakeSvmDual({{3.0, 0.0}, {0.5, 0.0}, {-2.0, 0.0}, {0.2, 0.0}}, {1, 1, 0, 0}, 1.0);
  ASSERT_TRUE(d.has_value());
  d->w = {1.0, 0.0};
  d->alpha = {0.0, 1.0, 0.0, 0.5};
  // G = (2, −0.5, 1, −1.2). Up: t0 (y+, α < C): −G = −2; t3 (y−, α > 0): G = −1.2. Low: t1: G = −0.5;
  // t2 (y−, α < C): −G = −1; t3: −G = 1.2.
  const SvmViolation v = MaxViolation(*d, AllPoints(4));
  EXPECT_DOUBLE_EQ(v.g_max1, -1.2);
  EXPECT_DOUBLE_EQ(v.g_max2, 1.2);
  std::vector<int> active = AllPoints(4);
  RemoveShrinkable(*d, v, &active);
  // t0 at 0, y+: out when G > g_max2 (2 > 1.2); t1 at C, y+: out when −G > g_max1 (0.5 > −1.2); t2 at 0,
  // y−: out when G > g_max1 (1 > −1.2); t3 is free and stays.
  EXPECT_EQ(active, (std::vector<int>{3}));
}

TEST(LinearSvmSteps, ShrinkActiveUnshrinksOnceWhenCloseToTheEnd) {
  SvmDual d = RandomDual(9, 25, 2.0);
  std::vector<int> active = {0, 1};
  bool unshrunk = false;
  // A threshold above any violation: every point comes back first, then the shrinkable ones leave.
  ShrinkActive(d, std::numeric_limits<double>::infinity(), &unshrunk, &active);
  EXPECT_TRUE(unshrunk);
  std::vector<int> expected = AllPoints(d.size());
  RemoveShrinkable(d, MaxViolation(d, expected), &expected);
  EXPECT_EQ(active, expected);
}

TEST(LinearSvmSteps, RhoIsTheMeanOverFreeVectorsElseTheMiddleOfTheBounds) {
  auto d = MakeSvmDual({{2.0, 0.0}, {-1.0, 0.0}, {0.5, 0.0}}, {1, 0, 1}, 1.0);
  ASSERT_TRUE(d.has_value());
  d->w = {1.0, 0.0};
  // y G: t0 = 2 − 1 = 1, t1 = −(1 − 1) = 0, t2 = 0.5 − 1 = −0.5.
  d->alpha = {0.5, 0.25, 0.0};
  EXPECT_DOUBLE_EQ(SvmRho(*d), 0.5);  // t0 and t1 free: (1 + 0) / 2
  // All at a bound: t0 at C with y+ bounds ρ from below by 1, t1 at 0 with y− from below by 0, t2 at 0 with
  // y+ from above by −0.5: ρ = (−0.5 + max(1, 0)) / 2.
  d->alpha = {1.0, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(SvmRho(*d), 0.25);
}

}  // namespace
}  // namespace semap::simplify
