// TrainLinearSvm against OpenCV's C_SVC (cv::ml::SVM, LINEAR; the solver PS used before) as reference.
#include "engine/simplify/internal/linear_svm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/ml.hpp>
#include <random>

namespace semap::simplify {
namespace {

struct Line {
  Eigen::Vector2d normal;  // unit
  double offset = 0.0;     // normal·x + offset = 0
};

Line FromDecision(const Eigen::Vector2d& w, double rho) { return {w / w.norm(), -rho / w.norm()}; }

Line OpenCvReference(const std::vector<Eigen::Vector2d>& x, const std::vector<int>& positive, double c) {
  const int n = static_cast<int>(x.size());
  cv::Mat samples(n, 2, CV_32F), responses(n, 1, CV_32S);
  for (int i = 0; i < n; ++i) {
    samples.at<float>(i, 0) = static_cast<float>(x[i].x());
    samples.at<float>(i, 1) = static_cast<float>(x[i].y());
    responses.at<int>(i, 0) = positive[i] ? 1 : -1;
  }
  auto svm = cv::ml::SVM::create();
  svm->setType(cv::ml::SVM::C_SVC);
  svm->setKernel(cv::ml::SVM::LINEAR);
  svm->setC(c);
  svm->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 2000, 1e-5));
  EXPECT_TRUE(svm->train(samples, cv::ml::ROW_SAMPLE, responses));
  const cv::Mat sv = svm->getSupportVectors();
  cv::Mat alpha, index;
  const double rho = svm->getDecisionFunction(0, alpha, index);
  alpha.convertTo(alpha, CV_64F);
  Eigen::Vector2d w = Eigen::Vector2d::Zero();
  for (int j = 0; j < index.cols * index.rows; ++j) {
    const int s = index.at<int>(j);
    w += alpha.at<double>(j) * Eigen::Vector2d(sv.at<float>(s, 0), sv.at<float>(s, 1));
  }
  return FromDecision(w, rho);
}

// Points in the unit disc (a region in region radii), labelled by a line through it, a share of the labels
// flipped near the line (overlapping classes).
void Region(std::uint64_t seed, double flip_band, std::vector<Eigen::Vector2d>* x,
            std::vector<int>* positive) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double angle = u(rng) * M_PI;
  const Eigen::Vector2d n(std::cos(angle), std::sin(angle));
  const double offset = 0.5 * u(rng);
  x->clear();
  positive->clear();
  while (x->size() < 200) {
    const Eigen::Vector2d p(u(rng), u(rng));
    if (p.norm() > 1.0) continue;
    const double d = n.dot(p) + offset;
    bool label = d > 0.0;
    if (std::abs(d) < flip_band && u(rng) > 0.3) label = !label;
    x->push_back(p);
    positive->push_back(label ? 1 : 0);
  }
}

// Overlapping regions run past n pair updates, so shrinking (every n updates) is exercised too.
TEST(LinearSvm, SameLineAsOpenCvsCSvc) {
  std::vector<Eigen::Vector2d> x;
  std::vector<int> positive;
  int shrunk = 0;  // problems that ran long enough to shrink
  for (double band : {0.0, 0.1, 0.3}) {
    for (std::uint64_t seed = 0; seed < 10; ++seed) {
      Region(seed, band, &x, &positive);
      const auto svm = TrainLinearSvm(x, positive, LinearSvmOptions{10.0, 1e-5, 2000});
      ASSERT_TRUE(svm.has_value());
      shrunk += svm->iterations > static_cast<int>(x.size());
      const Line got = FromDecision(svm->w, svm->rho);
      const Line want = OpenCvReference(x, positive, 10.0);
      // The same line up to the sign of the normal (the class order is the solver's choice).
      const double sign = got.normal.dot(want.normal) < 0.0 ? -1.0 : 1.0;
      EXPECT_GT(sign * got.normal.dot(want.normal), 0.999) << "band " << band << " seed " << seed;
      EXPECT_NEAR(sign * got.offset, want.offset, 0.01) << "band " << band << " seed " << seed;
    }
  }
  EXPECT_GT(shrunk, 0);
}

TEST(LinearSvm, SeparableMarginIsTheMidLine) {
  // Two points per class on either side of x = 0.5: the maximal margin line is x = 0.5.
  const std::vector<Eigen::Vector2d> x = {{0.0, 0.0}, {0.0, 1.0}, {1.0, 0.0}, {1.0, 1.0}};
  const auto svm = TrainLinearSvm(x, {0, 0, 1, 1}, LinearSvmOptions{});
  ASSERT_TRUE(svm.has_value());
  EXPECT_NEAR(svm->w.y(), 0.0, 1e-6);
  EXPECT_NEAR(svm->rho / svm->w.x(), 0.5, 1e-6);
  EXPECT_GT(svm->w.x(), 0.0);  // positive side = label 1
}

TEST(LinearSvm, OneClassOrTooFewPointsGiveNothing) {
  EXPECT_FALSE(TrainLinearSvm({{0.0, 0.0}, {1.0, 0.0}}, {1, 1}, LinearSvmOptions{}).has_value());
  EXPECT_FALSE(TrainLinearSvm({{0.0, 0.0}}, {1}, LinearSvmOptions{}).has_value());
  EXPECT_FALSE(TrainLinearSvm({}, {}, LinearSvmOptions{}).has_value());
}

}  // namespace
}  // namespace semap::simplify
