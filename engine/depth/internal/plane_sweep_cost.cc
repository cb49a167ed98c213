#include "engine/depth/internal/plane_sweep_cost.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace semap::depth_internal {
namespace {

// Grey levels are centred on this value before any sum (8-bit mid-grey).
constexpr double kMidGrey = 127.5;
// A homogeneous image coordinate w at or below this is at or behind the neighbour's image plane: the pixel
// maps nowhere (larger: pixels whose rays graze the neighbour's image plane are dropped too).
constexpr double kMinHomogeneousW = 1e-9;

cv::Mat WindowMean(const cv::Mat& src, int window_px, cv::Mat* dst) {
  cv::boxFilter(src, *dst, CV_32F, cv::Size(window_px, window_px), cv::Point(-1, -1), true,
                cv::BORDER_REPLICATE);
  return *dst;
}

}  // namespace

cv::Mat CentredGrey(const cv::Mat& grey) {
  cv::Mat centred;
  grey.convertTo(centred, CV_32F, 1.0, -kMidGrey);
  return centred;
}

ReferenceWindows MakeReferenceWindows(const cv::Mat& grey, int window_px, double min_stddev) {
  ReferenceWindows r;
  r.window_px = window_px;
  r.image = CentredGrey(grey);
  cv::Mat square, square_mean;
  WindowMean(r.image, window_px, &r.mean);
  cv::multiply(r.image, r.image, square);
  WindowMean(square, window_px, &square_mean);
  r.stddev.create(grey.size(), CV_32F);
  r.textured = cv::Mat::zeros(grey.size(), CV_8UC1);
  const int half = window_px / 2;
  const float floor_variance = static_cast<float>(min_stddev * min_stddev);
  for (int v = 0; v < grey.rows; ++v) {
    const float* m = r.mean.ptr<float>(v);
    const float* m2 = square_mean.ptr<float>(v);
    float* s = r.stddev.ptr<float>(v);
    std::uint8_t* t = r.textured.ptr<std::uint8_t>(v);
    const bool row_inside = v >= half && v < grey.rows - half;
    for (int u = 0; u < grey.cols; ++u) {
      const float variance = m2[u] - m[u] * m[u];
      s[u] = std::sqrt(std::max(variance, floor_variance));
      const bool inside = row_inside && u >= half && u < grey.cols - half;
      t[u] = (inside && variance >= floor_variance) ? 255 : 0;
    }
  }
  return r;
}

Eigen::Matrix3d PlaneHomography(const Eigen::Matrix3d& K_reference, const Eigen::Matrix3d& K_neighbour,
                                const Pose3d& neighbour_from_reference,
                                const Eigen::Vector3d& normal_reference, double offset_m) {
  const Eigen::Matrix3d R = neighbour_from_reference.linear();
  const Eigen::Vector3d t = neighbour_from_reference.translation();
  return K_neighbour * (R + t * normal_reference.transpose() / offset_m) * K_reference.inverse();
}

void WarpBand(const cv::Mat& neighbour, const Eigen::Matrix3d& reference_to_neighbour, int first_row,
              int rows, int width, WarpedBand* band) {
  // Band pixel (u, y) is reference pixel (u, first_row + y).
  Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
  shift(1, 2) = first_row;
  const Eigen::Matrix3d H = reference_to_neighbour * shift;
  cv::Matx33d H_cv;
  cv::eigen2cv(H, H_cv);
  // WARP_INVERSE_MAP: band(x) = neighbour(H x); outside the neighbour: 0, never a wrapped lookup.
  cv::warpPerspective(neighbour, band->image, H_cv, cv::Size(width, rows),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0));
  band->inside.create(rows, width, CV_8UC1);
  // The bilinear lookup reads pixels up to one to the right and below: inside means within [0, size − 1].
  const double max_x = neighbour.cols - 1, max_y = neighbour.rows - 1;
  for (int y = 0; y < rows; ++y) {
    std::uint8_t* in = band->inside.ptr<std::uint8_t>(y);
    Eigen::Vector3d p = H * Eigen::Vector3d(0.0, y, 1.0);
    const Eigen::Vector3d step = H.col(0);
    for (int u = 0; u < width; ++u, p += step) {
      bool ok = p.z() > kMinHomogeneousW;
      if (ok) {
        const double x = p.x() / p.z(), yy = p.y() / p.z();
        ok = x >= 0.0 && yy >= 0.0 && x <= max_x && yy <= max_y;
      }
      in[u] = ok ? 1 : 0;
    }
  }
}

void BandCost(const ReferenceWindows& reference, const WarpedBand& band, int band_first_row, int first_row,
              int rows, double min_stddev, CostScratch* scratch, cv::Mat* cost) {
  const int width = band.image.cols;
  const int half = reference.window_px / 2;
  const cv::Mat reference_band = reference.image(cv::Rect(0, band_first_row, width, band.image.rows));
  WindowMean(band.image, reference.window_px, &scratch->mean);
  cv::multiply(band.image, band.image, scratch->product);
  WindowMean(scratch->product, reference.window_px, &scratch->square_mean);
  cv::multiply(band.image, reference_band, scratch->product);
  WindowMean(scratch->product, reference.window_px, &scratch->cross_mean);
  cost->create(rows, width, CV_32F);
  const float floor_variance = static_cast<float>(min_stddev * min_stddev);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int r = 0; r < rows; ++r) {
    const int v = first_row + r;       // reference row
    const int y = v - band_first_row;  // band row
    float* c = cost->ptr<float>(r);
    const bool rows_inside = y - half >= 0 && y + half < band.image.rows;
    if (!rows_inside) {
      std::fill(c, c + width, nan);
      continue;
    }
    const std::uint8_t* top = band.inside.ptr<std::uint8_t>(y - half);
    const std::uint8_t* bottom = band.inside.ptr<std::uint8_t>(y + half);
    const float* mw = scratch->mean.ptr<float>(y);
    const float* mw2 = scratch->square_mean.ptr<float>(y);
    const float* mrw = scratch->cross_mean.ptr<float>(y);
    const float* mr = reference.mean.ptr<float>(v);
    const float* sr = reference.stddev.ptr<float>(v);
    for (int u = 0; u < width; ++u) {
      // The image of the window's rectangle is convex, and so is the neighbour's image: the window is
      // wholly inside when its four corners are.
      const bool inside = u - half >= 0 && u + half < width && top[u - half] && top[u + half] &&
                          bottom[u - half] && bottom[u + half];
      if (!inside) {
        c[u] = nan;
        continue;
      }
      const float variance = std::max(mw2[u] - mw[u] * mw[u], floor_variance);
      const float covariance = mrw[u] - mr[u] * mw[u];
      const float zncc = covariance / (sr[u] * std::sqrt(variance));
      c[u] = std::clamp(1.0f - zncc, 0.0f, kNoCost);
    }
  }
}

float AggregateCosts(const Aggregation& a, const float* costs, int count, float* scratch) {
  // The mean of the lowest best_views valid costs of the neighbours `in_subset` accepts; kNoCost with fewer
  // than min_views valid ones.
  auto aggregate = [&](auto in_subset) {
    int n = 0;
    for (int i = 0; i < count; ++i) {
      if (in_subset(i) && !std::isnan(costs[i])) scratch[n++] = costs[i];
    }
    if (n < a.min_views || n == 0) return kNoCost;
    const int k = a.best_views > 0 ? std::min(a.best_views, n) : n;
    if (k < n) std::nth_element(scratch, scratch + k, scratch + n);
    float sum = 0.0f;
    for (int i = 0; i < k; ++i) sum += scratch[i];
    return sum / static_cast<float>(k);
  };
  if (!a.subsets) return aggregate([](int) { return true; });
  const float left = aggregate([&](int i) { return bool(a.left[static_cast<size_t>(i)]); });
  const float right = aggregate([&](int i) { return !a.left[static_cast<size_t>(i)]; });
  return std::min(left, right);
}

}  // namespace semap::depth_internal
