// The paper's accuracy measure: per camera, the mesh's rendered depth against reference depths (Velodyne
// points projected into the image, or exact depth maps of generated sequences), at the same pixels.
//
// Definitions (both sides use the same depth: camera-frame z of the left camera, never LiDAR range):
// - reference pixels: pixels with a reference depth in [min_depth_m, max_depth_m]; a LiDAR point is
//   projected with cam_from_velo and the intrinsics, rounded to the nearest pixel, and only points in front
//   of the camera (z > min_depth_m) are kept; where several land on one pixel the nearest wins;
// - compared pixels: reference pixels where the mesh has a depth;
// - error = mesh depth − reference depth; RMSE, MAE, median |error| and mean error over compared pixels
//   (no outlier filter unless max_abs_error_m > 0: a hole is never an error, it lowers completeness);
// - completeness = compared pixels / reference pixels: a mesh with holes cannot look better than it is.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/frame.h"
#include "engine/core/options.h"

namespace semap {

struct DepthAccuracyOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  double min_depth_m = 1.0;
  double max_depth_m = 40.0;     // the depth stage's range
  double max_abs_error_m = 0.0;  // the 2018 authors used 2 m
  double surface_threshold_m = 0.2;
  int surface_pixel_stride = 8;
  int surface_area_samples = 100000;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("min_depth_m", &min_depth_m,
            "reference depths (camera-frame z, not range) nearer than this are ignored, m", Above(0));
    v.Field("max_depth_m", &max_depth_m,
            "reference depths farther than this are ignored, m; beyond min_depth_m");
    v.Field("max_abs_error_m", &max_abs_error_m,
            "errors above this are left out of RMSE/MAE (still count as covered); 0 = keep all", AtLeast(0));
    // Against the exact scene mesh: engine/eval/surface_metrics.h.
    v.Field("surface_threshold_m", &surface_threshold_m,
            "generated sequences: distance τ of accuracy / completeness against the exact scene mesh",
            Above(0));
    v.Field("surface_pixel_stride", &surface_pixel_stride,
            "generated sequences: exact depth maps sampled every this many pixels give the observed true "
            "surface",
            AtLeast(1));
    // The shares' standard sampling error is at most 0.5 / sqrt(n), 0.16 % at 100,000.
    v.Field(
        "surface_area_samples", &surface_area_samples,
        "generated sequences: points sampled uniformly by area on the mesh for the by-area accuracy (fixed "
        "seed)",
        AtLeast(1));
  }

  void Check() const;
};

// Two protocols are reported side by side:
// - strict: the options as configured (eval.*): reference depths in [min_depth_m, max_depth_m], every error
//   (max_abs_error_m = 0 by default);
// - paper: the 2018 authors' evaluator (shared/PRIOR_ART.md): reference depth ≤ 15 m and |error| ≤ 2 m only.
//   Their 15 m is a LiDAR range; here, as everywhere in semap, it is camera-frame z on both sides.
constexpr double kPaperMaxDepthM = 15.0;
constexpr double kPaperMaxAbsErrorM = 2.0;

// The paper protocol's filters on top of `strict`: max_depth_m = min(15 m, strict.max_depth_m),
// max_abs_error_m = 2 m; the rest (min_depth_m, surface figures) unchanged.
DepthAccuracyOptions PaperProtocol(const DepthAccuracyOptions& strict);

// What the filters of `options` are, for a report: "reference depth 1-40 m, every error" or
// "reference depth 1-15 m, |error| <= 2 m".
std::string ProtocolFilters(const DepthAccuracyOptions& options);

// Nearest camera-frame z per pixel of the Velodyne points (CV_32F, 0 = none), filtered as described above.
cv::Mat LidarDepthImage(const VelodyneScan& scan, const StereoCalibration& calibration,
                        const DepthAccuracyOptions& options);

struct DepthAccuracy {
  std::int64_t reference_pixels = 0;
  std::int64_t compared_pixels = 0;
  std::int64_t excluded_pixels =
      0;  // compared pixels left out of the error figures (|error| > max_abs_error_m)
  double rmse_m = 0.0;
  double mae_m = 0.0;
  double median_abs_m = 0.0;
  double mean_error_m = 0.0;  // signed: > 0 means the mesh is behind the reference
  double completeness = 0.0;
};

// Accumulates errors over pixels and frames. Not thread-safe; merge per-thread accumulators with Merge().
class DepthAccuracyAccumulator {
 public:
  explicit DepthAccuracyAccumulator(const DepthAccuracyOptions& options = {});
  // Adds the pixels of one camera: `reference` and `mesh` are CV_32F depth maps of the same size, 0 = none.
  void Add(const cv::Mat& reference, const cv::Mat& mesh);
  void Merge(const DepthAccuracyAccumulator& other);
  DepthAccuracy Result() const;

 private:
  DepthAccuracyOptions options_;
  std::int64_t reference_pixels_ = 0;
  std::int64_t outliers_ = 0;
  double sum_sq_ = 0.0;
  double sum_abs_ = 0.0;
  double sum_ = 0.0;
  std::vector<float> abs_errors_;  // for the median
};

}  // namespace semap
