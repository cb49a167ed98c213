#include "engine/depth/row_alignment.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>
#include <vector>

namespace semap {
namespace {

// FAST threshold (grey levels) of the corners matched, and at most this many of them (the strongest).
constexpr int kFastThreshold = 20;
constexpr int kMaxCorners = 3000;
// Pyramidal KLT: window side (px), levels above full resolution (reach about window · 2^levels px of
// disparity from a start at zero), stop criteria.
constexpr int kKltWindowPx = 11;
constexpr int kKltLevels = 5;
constexpr int kKltMaxIterations = 30;
constexpr double kKltEpsilonPx = 0.01;
// A match is kept when it tracks back into the left image this close to its start ...
constexpr double kMaxRoundTripPx = 0.3;
// ... its row offset is below this (larger ones are mismatches) and its disparity at least this, px.
constexpr double kMaxRowOffsetPx = 3.0;
constexpr double kMinDisparityPx = 1.0;
// Fewer matches than this: no fit. Six terms want many points spread over the image: a real KITTI pair
// gives ~2,300 (of kMaxCorners corners) and fits that agree from frame to frame within 0.1 px; a generated
// street's smooth textures give ~300, whose fits wander by ±0.3 px with nothing to correct.
constexpr int kMinMatches = 1000;
// Robust fit: rounds, residuals beyond this many σ (from the median |residual|) dropped before the next.
constexpr int kFitRounds = 3;
constexpr double kTrimSigmas = 3.0;
constexpr double kMadToSigma = 1.4826;

using Terms = Eigen::Matrix<double, RowOffsets::kTerms, 1>;

Terms TermsAt(const cv::Size& size, double u_px, double v_px) {
  const double w = size.width;
  const double x = (u_px - 0.5 * w) / w;
  const double y = (v_px - 0.5 * size.height) / w;
  Terms t;
  t << 1.0, x, y, x * y, x * x, y * y;
  return t;
}

double Median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::vector<RowMatch> MatchRows(const cv::Mat& left, const cv::Mat& right) {
  if ((left.type() != CV_8UC1 && left.type() != CV_8UC3) || left.type() != right.type() ||
      left.size() != right.size()) {
    throw std::invalid_argument("MatchRows: expected two 8-bit grey or BGR images of one size and type");
  }
  cv::Mat left_gray = left, right_gray = right;
  if (left.channels() == 3) {
    cv::cvtColor(left, left_gray, cv::COLOR_BGR2GRAY);
    cv::cvtColor(right, right_gray, cv::COLOR_BGR2GRAY);
  }
  std::vector<cv::KeyPoint> corners;
  cv::FAST(left_gray, corners, kFastThreshold, /*nonmaxSuppression=*/true);
  cv::KeyPointsFilter::retainBest(corners, kMaxCorners);
  if (corners.empty()) return {};
  std::vector<cv::Point2f> left_px, right_px, back_px;
  for (const cv::KeyPoint& k : corners) left_px.push_back(k.pt);
  const cv::Size window(kKltWindowPx, kKltWindowPx);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations,
                              kKltEpsilonPx);
  std::vector<cv::Mat> left_pyramid, right_pyramid;
  cv::buildOpticalFlowPyramid(left_gray, left_pyramid, window, kKltLevels);
  cv::buildOpticalFlowPyramid(right_gray, right_pyramid, window, kKltLevels);
  std::vector<uchar> found, found_back;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(left_pyramid, right_pyramid, left_px, right_px, found, error, window, kKltLevels,
                           stop);
  back_px = left_px;
  cv::calcOpticalFlowPyrLK(right_pyramid, left_pyramid, right_px, back_px, found_back, error, window, 1, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<RowMatch> matches;
  for (size_t i = 0; i < left_px.size(); ++i) {
    if (!found[i] || !found_back[i] || cv::norm(back_px[i] - left_px[i]) > kMaxRoundTripPx) continue;
    const double offset = right_px[i].y - left_px[i].y;
    if (std::abs(offset) > kMaxRowOffsetPx || left_px[i].x - right_px[i].x < kMinDisparityPx) continue;
    matches.push_back({left_px[i], right_px[i]});
  }
  return matches;
}

std::optional<RowOffsets> FitRowOffsets(const cv::Mat& left, const cv::Mat& right) {
  const std::vector<RowMatch> matches = MatchRows(left, right);
  std::vector<Terms> terms;
  std::vector<double> offsets;
  for (const RowMatch& m : matches) {
    terms.push_back(TermsAt(left.size(), m.right_px.x, m.right_px.y));
    offsets.push_back(m.right_px.y - m.left_px.y);
  }
  if (static_cast<int>(offsets.size()) < kMinMatches) return std::nullopt;
  std::vector<bool> keep(offsets.size(), true);
  Terms coefficients = Terms::Zero();
  double median_residual = 0.0;
  int kept = 0;
  for (int round = 0; round < kFitRounds; ++round) {
    Eigen::Matrix<double, RowOffsets::kTerms, RowOffsets::kTerms> normal;
    normal.setZero();
    Terms rhs = Terms::Zero();
    kept = 0;
    for (size_t i = 0; i < offsets.size(); ++i) {
      if (!keep[i]) continue;
      normal += terms[i] * terms[i].transpose();
      rhs += terms[i] * offsets[i];
      ++kept;
    }
    if (kept < kMinMatches) return std::nullopt;
    coefficients = normal.ldlt().solve(rhs);
    std::vector<double> residuals(offsets.size());
    for (size_t i = 0; i < offsets.size(); ++i)
      residuals[i] = std::abs(terms[i].dot(coefficients) - offsets[i]);
    median_residual = Median(residuals);
    for (size_t i = 0; i < offsets.size(); ++i) {
      keep[i] = residuals[i] <= kTrimSigmas * kMadToSigma * median_residual;
    }
  }
  if (!coefficients.allFinite()) return std::nullopt;
  double max_abs = 0.0;
  for (size_t i = 0; i < offsets.size(); ++i) {
    if (keep[i]) max_abs = std::max(max_abs, std::abs(terms[i].dot(coefficients)));
  }
  RowOffsets fit;
  for (int k = 0; k < RowOffsets::kTerms; ++k) fit.coefficients_px[static_cast<size_t>(k)] = coefficients[k];
  fit.image_size = left.size();
  fit.matches = kept;
  fit.median_residual_px = median_residual;
  fit.max_abs_px = max_abs;
  return fit;
}

cv::Mat AlignRows(const cv::Mat& right, const RowOffsets& offsets) {
  if (right.size() != offsets.image_size) {
    throw std::invalid_argument("AlignRows: row offsets fitted on another image size");
  }
  // Along a row the model is a quadratic in x: a + b x + c x², with a, b, c from the row's y.
  const std::array<double, RowOffsets::kTerms>& k = offsets.coefficients_px;
  const double w = right.cols;
  cv::Mat map_x(right.size(), CV_32FC1), map_y(right.size(), CV_32FC1);
  for (int v = 0; v < right.rows; ++v) {
    const double y = (v - 0.5 * right.rows) / w;
    const double a = k[0] + k[2] * y + k[5] * y * y;
    const double b = k[1] + k[3] * y;
    const double c = k[4];
    float* mx = map_x.ptr<float>(v);
    float* my = map_y.ptr<float>(v);
    for (int u = 0; u < right.cols; ++u) {
      const double x = (u - 0.5 * w) / w;
      mx[u] = static_cast<float>(u);
      my[u] = static_cast<float>(v + std::clamp(a + (b + c * x) * x, -kMaxRowOffsetPx, kMaxRowOffsetPx));
    }
  }
  cv::Mat aligned;
  cv::remap(right, aligned, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return aligned;
}

}  // namespace semap
