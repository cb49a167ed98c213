// A linear soft-margin SVM (C-SVC) on 2-D points: the class boundary of PS's boundary regions. Not API.
//
// The same problem as libsvm's / OpenCV's C_SVC with a LINEAR kernel (cv::ml::SVM, which PS used before):
// min ½|w|² + C Σ ξ_i subject to y_i (w·x_i − ρ) ≥ 1 − ξ_i, solved in the dual by SMO with libsvm's
// second-order working-set selection, stopping when the maximal KKT violation is below `epsilon` or after
// `max_iterations` passes, and ρ from the free support vectors as libsvm computes it. Written for PS's
// small problems (at most ps_svm_max_samples points): no kernel cache, every step O(n) on the points
// themselves, no allocation beyond the per-point arrays; libsvm's shrinking (points at a bound that no
// working set can pick leave the scans; the end is judged on every point). Deterministic; thread-safe (no
// state).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace semap::simplify {

struct LinearSvmOptions {
  double c = 10.0;            // soft-margin C
  double epsilon = 1e-5;      // stop when the maximal KKT violation is below this
  int max_iterations = 2000;  // pair updates at most
};

struct LinearSvm {
  Eigen::Vector2d w = Eigen::Vector2d::Zero();  // decision(x) = w·x − rho; positive = label true
  double rho = 0.0;
  int iterations = 0;
};

// Trains on `x` with labels `positive` (same size). nullopt with fewer than two points or one class only.
std::optional<LinearSvm> TrainLinearSvm(const std::vector<Eigen::Vector2d>& x,
                                        const std::vector<int>& positive, const LinearSvmOptions& options);

}  // namespace semap::simplify
