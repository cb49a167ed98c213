// Depth stage: rectified stereo pair → disparity (OpenCV semi-global matching) → labelled point cloud in the
// world frame. The cloud carries position, pixel, colour, a disparity confidence and the observing camera;
// labels are added by the semantic stage (engine/semantics/labelling.h).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "engine/core/frame.h"
#include "engine/core/labelled_cloud.h"

namespace semap {

// OpenCV StereoSGBM modes: 5-direction single pass (sgbm), full 8-direction (hh), 3-way parallel (3way),
// 4-direction (hh4).
enum class SgbmMode { kSgbm, kHh, kThreeWay, kHh4 };

const char* SgbmModeName(SgbmMode mode);

struct DepthOptions {
  // --- Matching (OpenCV StereoSGBM; see cv::StereoSGBM::create) ---
  // Disparity search range in px at full resolution (multiple of 16). KITTI at 1242 px: 128 covers ≥ 2.9 m.
  int num_disparities = 128;
  // Matched block size in px (odd, 1..11).
  int block_size = 7;
  // Smoothness penalties for disparity changes of 1 px (P1) and > 1 px (P2); 0 = 8·C·block² and 32·C·block²
  // with C the number of image channels (OpenCV's recommendation). Requires P2 > P1 when both are set.
  int p1 = 0;
  int p2 = 0;
  // Margin in % by which the best cost must beat the second best (0 = no uniqueness test).
  int uniqueness_ratio = 5;
  // Speckle filter: connected regions of at most this many px (0 = off) whose disparity varies by at most
  // speckle_range px are invalidated.
  int speckle_window_size = 100;
  int speckle_range_px = 2;
  // OpenCV's built-in left-right check (disp12MaxDiff, from the same cost volume; -1 = off). OpenCV 4.6
  // applies it in modes sgbm/hh/hh4 only, not in 3way.
  int disp12_max_diff_px = 1;
  // Explicit left-right consistency check (any mode): a second SGBM pass matches the right image against the
  // left; a left pixel u with disparity d is kept when the right disparity at u − d differs by at most this
  // many px. Costs a second matching pass. -1 = off.
  float left_right_max_diff_px = -1.0f;
  // Truncation of the x-derivative prefilter (OpenCV preFilterCap; 0 = OpenCV's default).
  int pre_filter_cap = 31;
  SgbmMode mode = SgbmMode::kThreeWay;
  // Match at half resolution (both images downscaled by 2, disparity upscaled back): about 4× faster.
  bool half_resolution = false;

  // --- Post-processing of the disparity ---
  // Fill horizontal gaps of invalid disparity of at most this many px lying between two valid pixels on a row
  // with the smaller (farther, background) of the two (KITTI's interpolation rule); 0 = off.
  int fill_max_gap_px = 64;
  // Fill the unmatched band on the left image border (the first num_disparities columns, which SGBM cannot
  // match) with the first valid disparity of the row. The filled pixels have confidence 0.
  bool fill_left_border = true;
  // Confidence given to pixels filled by the small-gap filling (matched pixels get 1).
  float filled_confidence = 0.5f;

  // --- Point cloud ---
  // Depth range of the emitted points (camera-frame z).
  double min_depth_m = 1.0;
  double max_depth_m = 40.0;
  // Only every pixel_stride-th pixel on every pixel_stride-th row gives a point (1 = every pixel). With
  // half_resolution the stride is doubled (one point per matched half-resolution pixel, no duplicates).
  int pixel_stride = 1;
  // Point budget per frame after the stride, by uniform decimation (0 = dense). The default is what the
  // incremental map sustains at about 1 frame/s on one core (bench/RESULTS.md); dense SGBM frames have ~350k.
  int max_points_per_frame = 10000;
  // Pixels whose confidence is below this give no point. The default 1 keeps matched pixels only: the filled
  // pixels improve the disparity map (D1) but are guesses, kept out of the map.
  float min_point_confidence = 1.0f;
  // The depth map handed to the map's visibility votes keeps one pixel in vote_stride_px on every
  // vote_stride_px-th row (full-resolution px; each stands for vote_stride_px² rays). Every valid pixel there
  // votes, whatever the point budget above.
  int vote_stride_px = 1;

  // Throws InvalidOption naming the field on a value out of range.
  void Check() const;
};

// A disparity map and its per-pixel confidence, both the size of the left image.
struct DisparityResult {
  cv::Mat disparity_px;  // CV_32F, disparity in full-resolution px; invalid = 0 (never NaN or infinite)
  cv::Mat confidence;    // CV_32F in [0, 1]: 1 matched, filled_confidence small-gap filled, 0 border-filled
};

// The depth stage. Stateless apart from its options: const methods may be called from several threads at once
// (each call builds its own OpenCV matcher).
class StereoDepth {
 public:
  // Checks the options (throws InvalidOption).
  explicit StereoDepth(const DepthOptions& options);

  const DepthOptions& options() const { return options_; }

  // Disparity of the left image. Requires two non-empty images of the same size and type, both CV_8UC1 or
  // both CV_8UC3 (throws std::invalid_argument naming the mismatch otherwise). Invalid pixels are 0. An image
  // no wider than num_disparities (at the matching resolution) cannot be matched: every pixel is invalid.
  DisparityResult Compute(const cv::Mat& left, const cv::Mat& right) const;
  // Compute(left, right).disparity_px.
  cv::Mat ComputeDisparity(const cv::Mat& left, const cv::Mat& right) const;

  // Points of the frame's left camera from a disparity map the size of frame.left (and optionally its
  // confidence, same size, CV_32F; empty = every valid pixel has confidence 1), in the world frame via
  // frame.world_from_cam (identity when absent). Pixels with a disparity ≤ 0 or non-finite, a depth outside
  // [min_depth_m, max_depth_m] or a confidence below min_point_confidence give no point; a map without any
  // valid pixel gives an empty cloud (with its camera). The cloud has one camera (index 0: the left camera's
  // centre, frame.id), pixels, colours (RGB, grey replicated), confidence, and no labels.
  // Throws std::invalid_argument on a size/type mismatch or an invalid calibration.
  LabelledCloud ToCloud(const Frame& frame, const cv::Mat& disparity_px,
                        const cv::Mat& confidence = cv::Mat()) const;

  // The depth map of the map's visibility votes: every vote_stride_px-th pixel of `disparity_px`, as
  // camera-frame depth; pixels that would give no point (invalid, out of range, low confidence) are 0.
  DepthView ToDepthView(const Frame& frame, const cv::Mat& disparity_px, const cv::Mat& confidence = cv::Mat()) const;

  // Compute(), then ToCloud() with the ToDepthView() of its camera.
  LabelledCloud Process(const Frame& frame) const;

 private:
  DepthOptions options_;
};

}  // namespace semap
