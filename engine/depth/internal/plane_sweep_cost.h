// The plane sweep's pieces below its public API (engine/depth/plane_sweep.h): plane homographies, warping a
// band of reference rows out of a neighbour with a validity mask, the ZNCC cost of a warped band, and the
// aggregation of the views' costs.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "engine/core/calibration.h"

namespace semap::depth_internal {

// The cost of a plane that is not scored at a pixel (too few views see it): the worst ZNCC cost, 1 − (−1).
inline constexpr float kNoCost = 2.0f;

// The reference image's window statistics, shared by every plane and view. All CV_32F, the image's size.
struct ReferenceWindows {
  int window_px = 0;
  cv::Mat image;   // grey levels, centred on mid-grey (smaller sums, less cancellation in the variances)
  cv::Mat mean;    // window mean of `image`
  cv::Mat stddev;  // window standard deviation, floored at the options' min_window_stddev
  cv::Mat
      textured;  // CV_8UC1, 255 where the window lies inside the image and its deviation reaches the floor
};
ReferenceWindows MakeReferenceWindows(const cv::Mat& grey, int window_px, double min_stddev);

// Grey levels as CV_32F centred on mid-grey (the same transform as ReferenceWindows::image).
cv::Mat CentredGrey(const cv::Mat& grey);

// Reference pixels → neighbour pixels for the plane nᵀX = d of the reference frame (plane_sweep.h's
// convention): K_n (R + t nᵀ / d) K_ref⁻¹ with [R | t] = neighbour_from_reference.
Eigen::Matrix3d PlaneHomography(const Eigen::Matrix3d& K_reference, const Eigen::Matrix3d& K_neighbour,
                                const Pose3d& neighbour_from_reference,
                                const Eigen::Vector3d& normal_reference, double offset_m);

// A band of reference rows [first_row, first_row + rows) seen through a homography from one neighbour.
struct WarpedBand {
  cv::Mat image;  // CV_32F, rows × reference width; bilinear; 0 where the pixel maps outside
  cv::Mat
      inside;  // CV_8UC1: 1 where the pixel maps in front of the neighbour, inside its image (never wrapped)
};
// Warps `neighbour` (CentredGrey) into `band` (its buffers reused when their size fits).
void WarpBand(const cv::Mat& neighbour, const Eigen::Matrix3d& reference_to_neighbour, int first_row,
              int rows, int width, WarpedBand* band);

// Scratch buffers of BandCost, reused across calls by one thread.
struct CostScratch {
  cv::Mat product, mean, square_mean, cross_mean;
};

// 1 − ZNCC of each pixel's window between the reference and `band` (which starts at reference row
// band_first_row), for the reference rows [first_row, first_row + rows) (inside the band, with the window's
// half-side above and below where the image has them). `cost` (CV_32F, rows × width) gets the cost in [0, 2],
// or NaN where the window is not wholly inside the neighbour. The warped window's variance is floored as
// the reference's is, so a flat warped window scores near 1, never better.
void BandCost(const ReferenceWindows& reference, const WarpedBand& band, int band_first_row, int first_row,
              int rows, double min_stddev, CostScratch* scratch, cv::Mat* cost);

// How the neighbours' costs at one pixel and plane become one cost.
struct Aggregation {
  int best_views = 0;      // mean of the lowest best_views costs (0 = all)
  int min_views = 1;       // fewer valid costs than this: kNoCost
  std::vector<bool> left;  // per neighbour: in the left subset (used when subsets is true)
  bool subsets = false;    // the lower of the left and right subsets' aggregates
};
// `costs`: one per neighbour, NaN = that neighbour does not see the window. `scratch` holds at least as many.
float AggregateCosts(const Aggregation& a, const float* costs, int count, float* scratch);

}  // namespace semap::depth_internal
