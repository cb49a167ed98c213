// Depth stage: rectified stereo pair → disparity (OpenCV semi-global matching) → labelled point cloud in the
// world frame. The cloud carries position, pixel, colour, a disparity confidence and the observing camera;
// labels are added by the semantic stage (engine/semantics/labelling.h).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "engine/core/frame.h"
#include "engine/core/labelled_cloud.h"
#include "engine/core/options.h"

namespace semap {

// OpenCV StereoSGBM modes: 5-direction single pass (sgbm), full 8-direction (hh), 3-way parallel (3way),
// 4-direction (hh4).
enum class SgbmMode { kSgbm, kHh, kThreeWay, kHh4 };

const char* SgbmModeName(SgbmMode mode);

struct DepthOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).

  // Matching (OpenCV StereoSGBM; see cv::StereoSGBM::create).
  int num_disparities = 128;  // KITTI at 1242 px: covers >= 2.9 m
  int block_size = 7;
  int p1 = 0;
  int p2 = 0;
  int uniqueness_ratio = 5;
  int speckle_window_size = 100;
  int speckle_range_px = 2;
  int disp12_max_diff_px = 1;
  float left_right_max_diff_px = -1.0f;
  bool left_right_half_resolution = false;
  int pre_filter_cap = 31;
  SgbmMode mode = SgbmMode::kThreeWay;
  bool half_resolution = false;
  bool align_rows = true;
  double align_rows_min_px = 0.25;

  // Post-processing of the disparity.
  int fill_max_gap_px = 64;
  bool fill_left_border = true;
  float filled_confidence = 0.5f;

  // Point cloud.
  double min_depth_m = 1.0;
  double max_depth_m = 40.0;
  int pixel_stride = 1;
  int max_points_per_frame = 10000;
  float min_point_confidence = 1.0f;
  int vote_stride_px = 1;

  // OpenCV's SGBM: the disparity range is a multiple of 16, the block size at most 11.
  static constexpr int kDisparityMultiple = 16;
  static constexpr int kMaxBlockSize = 11;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("num_disparities", &num_disparities, "disparity search range in px at full resolution",
            AtLeast(kDisparityMultiple).MultipleOf(kDisparityMultiple));
    v.Field("block_size", &block_size, "SGBM matched block size in px", In(1, kMaxBlockSize).Odd());
    v.Field("p1", &p1,
            "SGBM penalty for 1 px disparity changes; 0 = 8*channels*block_size^2 (OpenCV's recommendation)",
            AtLeast(0));
    v.Field(
        "p2", &p2,
        "SGBM penalty for larger disparity changes; 0 = 32*channels*block_size^2; must exceed p1 when both "
        "are set",
        AtLeast(0));
    v.Field("uniqueness_ratio", &uniqueness_ratio,
            "margin in % by which the best cost must beat the second best (0 = no uniqueness test)",
            In(0, 100));
    v.Field("speckle_window_size", &speckle_window_size,
            "speckle filter: connected regions of at most this many px whose disparity varies by at most "
            "speckle_range_px are invalidated (0 = off)",
            AtLeast(0));
    v.Field("speckle_range_px", &speckle_range_px, "speckle filter: disparity variation within a region",
            AtLeast(0));
    // OpenCV 4.6 applies disp12MaxDiff in modes sgbm/hh/hh4 only, not in 3way.
    v.Field("disp12_max_diff_px", &disp12_max_diff_px,
            "OpenCV's left-right check from the same cost volume: max left/right disparity difference in px",
            AtLeast(0).Or(-1, "off"));
    v.Field(
        "left_right_max_diff_px", &left_right_max_diff_px,
        "explicit left-right check (any mode) with a second matching pass, right against left: a pixel is "
        "kept when the two disparities differ by at most this many px",
        AtLeast(0).Or(-1, "off"));
    v.Field("left_right_half_resolution", &left_right_half_resolution,
            "the left-right check's right-image pass at half resolution (a quarter of its cost)");
    v.Field("pre_filter_cap", &pre_filter_cap, "SGBM x-derivative prefilter truncation (0 = OpenCV default)",
            In(0, 63));
    // KITTI's real pairs are off by up to 0.7 px (odometry 04) and 1.6 px (kitti_odometry_turn) at the
    // corners; lining the rows up lowers KITTI 04's SGBM median error by 4 % and the map's static bias at
    // 20-30 m from +0.16 to +0.05 m (bench/results/map-accuracy.md, "rows lined up"). See
    // engine/depth/row_alignment.h.
    v.Field(
        "align_rows", &align_rows,
        "measure the pair's residual vertical misalignment (sparse stereo matches, a quadratic over the "
        "image; "
        "semap run measures it on its first frames, then every 100) and move the right image's rows by it "
        "before matching");
    v.Field("align_rows_min_px", &align_rows_min_px,
            "align_rows leaves a pair alone whose fitted misalignment stays below this everywhere, px (a "
            "rectified pair is not resampled)",
            AtLeast(0));
    v.Enum("mode", &mode,
           {{"sgbm", SgbmMode::kSgbm},
            {"hh", SgbmMode::kHh},
            {"3way", SgbmMode::kThreeWay},
            {"hh4", SgbmMode::kHh4}},
           "OpenCV SGBM mode");
    v.Field("half_resolution", &half_resolution,
            "match at half resolution, disparity upscaled back (about 4x faster; doubles pixel_stride)");
    v.Field("fill_max_gap_px", &fill_max_gap_px,
            "fill horizontal gaps up to this many px between two valid pixels of a row with the background "
            "(smaller) disparity, KITTI's interpolation rule (0 = off)",
            AtLeast(0));
    v.Field("fill_left_border", &fill_left_border,
            "extend each row's first valid disparity over the unmatched left band (confidence 0)");
    v.Field("filled_confidence", &filled_confidence, "confidence of gap-filled pixels (matched = 1)",
            In(0, 1));
    v.Field("min_depth_m", &min_depth_m, "nearest point kept (camera-frame z, m)", Above(0));
    v.Field("max_depth_m", &max_depth_m, "farthest point kept (camera-frame z, m); beyond min_depth_m");
    v.Field("pixel_stride", &pixel_stride,
            "one point every pixel_stride px on every pixel_stride-th row (1 = every pixel; doubled with "
            "half_resolution: one point per matched pixel)",
            AtLeast(1));
    // Points offered to the simplification and the map's insertion; every valid pixel votes whatever it is
    // (vote_stride_px). Dense SGBM frames have ~350 k valid pixels. At half resolution, one point per matched
    // pixel, 10,000 are 10 % of a frame's valid pixels against 2.5 % at full resolution: there 6,000 ran 200
    // urban frames 15 % faster, with accuracy within ±4 % either way on four sequences (bench/results/
    // frame-rate.md, "The point budget at half resolution").
    v.Field("max_points_per_frame", &max_points_per_frame,
            "point budget per frame after the stride, by uniform decimation (0 = none)", AtLeast(0));
    // The default keeps matched pixels only: the filled pixels improve the disparity map (D1) but are
    // guesses, kept out of the map.
    v.Field("min_point_confidence", &min_point_confidence, "pixels below this confidence give no point",
            In(0, 1));
    v.Field(
        "vote_stride_px", &vote_stride_px,
        "the map's visibility votes read one pixel in vote_stride_px on every vote_stride_px-th row of the "
        "depth map, each standing for vote_stride_px² rays (map.visibility: depth); every valid one votes, "
        "whatever max_points_per_frame",
        AtLeast(1));
  }

  void Check() const;
};

// A disparity map and its per-pixel confidence, both the size of the left image.
struct DisparityResult {
  cv::Mat disparity_px;  // CV_32F, disparity in full-resolution px; invalid = 0 (never NaN or infinite)
  cv::Mat confidence;    // CV_32F in [0, 1]: 1 matched, filled_confidence small-gap filled, 0 border-filled
  double rows_aligned_px = 0.0;  // align_rows: the largest row offset removed from the right image (0: none)
};

// The camera-frame depth (m) of every pixel of a CV_32F disparity map with a disparity > 0 (f·B / d with the
// calibration's focal length and baseline), 0 elsewhere: SGBM's, or a plane sweep's in that form.
cv::Mat DepthMapFromDisparity(const cv::Mat& disparity_px, const StereoCalibration& calibration);

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
  // With align_rows, the right image's rows are first lined up with the left's by `row_offsets` (the rig's,
  // as measured earlier: RowAlignmentReader), or, when null, by a fit on this pair (FitRowOffsets: ~30 ms
  // more), when the misalignment reaches align_rows_min_px.
  DisparityResult Compute(const cv::Mat& left, const cv::Mat& right,
                          const RowOffsets* row_offsets = nullptr) const;
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
  DepthView ToDepthView(const Frame& frame, const cv::Mat& disparity_px,
                        const cv::Mat& confidence = cv::Mat()) const;

  // Compute(), then ToCloud() with the ToDepthView() of its camera.
  LabelledCloud Process(const Frame& frame) const;

 private:
  DepthOptions options_;
};

}  // namespace semap
