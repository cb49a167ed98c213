// Multi-view depth by plane sweeping: a reference view and N calibrated neighbour views (any poses, no stereo
// rig) → a depth map of the reference. Each plane of a family (fronto-parallel, or a caller's direction such
// as the ground or a facade) warps every neighbour into the reference through its homography; ZNCC over a
// window scores each plane at each pixel, an occlusion-robust aggregation over the views picks the best, and
// a parabola through the neighbouring planes refines it. Optionally a pixel keeps its depth only where
// enough neighbours, each on its own, agree with the winning plane (min_agreeing_views).
//
// Plane convention: a plane of normal n (unit, in the reference camera's frame) and offset d > 0 is the set
// of reference-camera points X with nᵀX = d. With cam_from_ref = [R | t] (neighbour camera from reference
// camera) a point of that plane maps as X_n = R X + t (nᵀX) / d, so the homography from reference pixels to
// neighbour pixels is H = K_n (R + t nᵀ / d) K_ref⁻¹ (the textbook K_n (R − t nᵀ / d) K_ref⁻¹ writes the
// plane as nᵀX + d = 0). The pixel x̃ = (u, v, 1) of the reference meets the plane at depth (camera-frame z)
// d / (nᵀ K_ref⁻¹ x̃); for the fronto-parallel family n = (0, 0, 1) and the depth is d.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/frame.h"
#include "engine/core/options.h"

namespace semap {

// One calibrated view: a grey (CV_8UC1) image, its pinhole intrinsics (pixels; no distortion) and its pose.
using PlaneSweepView = CalibratedView;

// The depths swept, camera-frame z of the reference, in metres.
struct DepthRange {
  double min_depth_m = 0.0;
  double max_depth_m = 0.0;
};

struct PlaneSweepOptions {
  // Each field's key and meaning: Describe() below, once.
  int num_planes = 128;      // per family; more: finer steps, proportionally slower
  double min_depth_m = 0.0;  // both 0: from the cameras (DepthRangeFromCameras)
  double max_depth_m = 0.0;
  double camera_range_factor = 2.5;
  int window_px = 7;
  double min_window_stddev = 2.0;
  int best_views = 2;
  bool left_right_subsets = false;
  int min_views = 1;
  double max_cost = 0.6;
  double min_confidence = 0.05;
  int min_agreeing_views = 0;  // 0: off
  int agreement_planes = 2;
  double agreement_max_cost = 0.5;
  bool label_directions = true;
  // Stereo frames swept beside SGBM (engine/depth/stereo_sweep.h).
  int stereo_past_frames = 0;  // 0: SGBM alone
  double stereo_min_depth_m = 15.0;
  double stereo_max_depth_m = 60.0;
  int stereo_window_px = 11;
  int stereo_best_views = 0;  // 0: the mean of all views
  double stereo_parallax_gain = 1.0;
  double stereo_max_disagreement_px = 1.0;

  // Each field's key, text and valid values, declared once here (engine/core/options.h); Check() tests the
  // values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("num_planes", &num_planes,
            "planes per sweep direction, uniform in inverse depth between min_depth_m and max_depth_m (more: "
            "finer depth steps, cost grows with it)",
            AtLeast(3));
    v.Field("min_depth_m", &min_depth_m,
            "nearest depth swept (reference camera-frame z, m); 0 together with max_depth_m = 0: the range "
            "comes from the cameras (where their optical axes meet, divided and multiplied by "
            "camera_range_factor)",
            AtLeast(0));
    v.Field("max_depth_m", &max_depth_m,
            "farthest depth swept (m), beyond min_depth_m; 0 with min_depth_m = 0: from the cameras",
            AtLeast(0));
    v.Field("camera_range_factor", &camera_range_factor,
            "the range from the cameras spans [z / factor, z · factor] around the depth z where the optical "
            "axes meet (larger: surfaces farther from that depth are found, with coarser steps)",
            Above(1));
    v.Field("window_px", &window_px,
            "ZNCC window side in px (larger: smoother and more reliable, blurs depth edges)",
            AtLeast(3).Odd());
    v.Field("min_window_stddev", &min_window_stddev,
            "floor on a window's grey-level standard deviation: reference windows below it are textureless "
            "and give no depth; the floor also damps the score of flat warped windows (higher: fewer, surer "
            "pixels)",
            Above(0));
    v.Field("best_views", &best_views,
            "a plane's cost at a pixel is the mean of its best best_views neighbours' costs, which ignores "
            "the views where the pixel is occluded (0 = the mean of all views)",
            AtLeast(0));
    v.Field("left_right_subsets", &left_right_subsets,
            "also aggregate the neighbours left and right of the reference separately (by the sign of their "
            "centre's x in the reference frame) and keep the lower cost: an occlusion hides a pixel from "
            "one side only");
    v.Field("min_views", &min_views,
            "neighbours that must see a pixel's whole window at a plane for that plane to be scored there",
            AtLeast(1));
    v.Field("max_cost", &max_cost,
            "pixels whose best aggregated cost (1 − ZNCC, in [0, 2]) exceeds this give no depth (lower: "
            "fewer, surer pixels)",
            Above(0).AtMost(2));
    v.Field("min_confidence", &min_confidence,
            "pixels whose confidence 1 − best / second-best local minimum of the cost falls below this give "
            "no depth (higher: fewer ambiguous pixels)",
            In(0, 1));
    v.Field("min_agreeing_views", &min_agreeing_views,
            "pixels where fewer neighbours than this agree with the winning plane give no depth: a neighbour "
            "agrees when its own lowest cost over the winner's planes lies within agreement_planes planes of "
            "the winner and its cost at the winner is at most agreement_max_cost; a frame with fewer "
            "neighbours needs all of them (higher: fewer pixels, those seen alike by more views; 0 = off)",
            AtLeast(0));
    v.Field(
        "agreement_planes", &agreement_planes,
        "how far, in planes, a neighbour's own lowest cost may lie from the winning plane for it to agree "
        "(lower: a stricter agreement, fewer pixels)",
        AtLeast(0));
    v.Field("agreement_max_cost", &agreement_max_cost,
            "highest cost (1 − ZNCC) of an agreeing neighbour at the winning plane (lower: a stricter "
            "agreement, fewer pixels; 2 = no bound on the cost)",
            Above(0).AtMost(2));
    // A frame where directions were found is swept a second time, both families: more pixels with a depth
    // and a lower median error on slanted ground and facades, for about twice and a half the sweep's time
    // (bench/RESULTS.md, "Plane sweep"). Without ground or wall labels nothing changes.
    v.Field("label_directions", &label_directions,
            "multi-view frames: after a fronto-parallel sweep, fit a RANSAC plane to the ground's and the "
            "walls' labelled pixels and sweep again with planes parallel to each (offsets within 20 % of "
            "the fitted plane's distance): slanted ground and facades get their depth");
    // The sweep beside SGBM costs a sweep of num_planes planes per frame (bench/RESULTS.md, "Multi-view
    // depth"): several SGBM frames' time, beyond the real-time budget; off by default.
    v.Field("stereo_past_frames", &stereo_past_frames,
            "stereo frames (a right image and a pose): also sweep the left image against the right one and "
            "the left images of this many earlier frames, and take the sweep's depth where its neighbours' "
            "parallax beats the pair's (stereo_parallax_gain) and it agrees with SGBM's "
            "(stereo_max_disagreement_px); 0 = SGBM alone",
            AtLeast(0));
    v.Field(
        "stereo_min_depth_m", &stereo_min_depth_m,
        "stereo frames: nearest depth swept (m); SGBM keeps every pixel it puts nearer (larger: the sweep "
        "serves far surfaces only, with finer steps)",
        Above(0));
    v.Field("stereo_max_depth_m", &stereo_max_depth_m,
            "stereo frames: farthest depth swept (m), beyond stereo_min_depth_m");
    v.Field("stereo_window_px", &stereo_window_px,
            "stereo frames: the ZNCC window side in px (window_px for them; larger: surer far depth, blurred "
            "depth edges)",
            AtLeast(3).Odd());
    // A forward-moving rig's earlier frames see the middle of the image with little parallax: they match
    // there at every depth, and a best-views aggregation would keep them and flatten the cost.
    v.Field("stereo_best_views", &stereo_best_views,
            "stereo frames: best_views for them (0 = the mean of all views)", AtLeast(0));
    v.Field("stereo_parallax_gain", &stereo_parallax_gain,
            "stereo frames: the sweep's depth replaces SGBM's at a pixel where its best best_views "
            "neighbours' mean parallax (px per unit of inverse depth) is at least this many times the "
            "pair's f·B (higher: the sweep serves only where its baselines are much longer)",
            Above(0));
    v.Field(
        "stereo_max_disagreement_px", &stereo_max_disagreement_px,
        "stereo frames: the sweep's depth replaces SGBM's only within this many px of the pair's "
        "disparity (lower: the sweep refines SGBM's depth, never overrules it; -1 = no bound); where SGBM "
        "gives none, the pixel stays without",
        AtLeast(0).Or(-1, "no bound"));
  }

  void Check() const;
};

// A direction of planes swept besides the fronto-parallel one (the ground, a facade): the world planes
// nᵀX = c, n = normal_world / |normal_world|, with c in [min_offset_m, max_offset_m]. Both offsets 0: every
// plane of that normal that crosses the depth range somewhere in the reference image; such a sweep spans a
// wider range of planes than the fronto-parallel one (rays that graze the planes need planes near the
// camera), so its steps are coarser: give the offsets when they are known (a plane fitted to sparse points,
// with a margin).
struct SweepDirection {
  Eigen::Vector3d normal_world = Eigen::Vector3d::UnitY();
  double min_offset_m = 0.0;
  double max_offset_m = 0.0;
};

// Which sweep direction won at a pixel: 0 the fronto-parallel planes, k ≥ 1 directions[k − 1].
inline constexpr std::uint8_t kNoFamily = 255;  // no depth at the pixel

// The reference view's depth. Invalid pixels have depth 0 (never NaN), confidence 0, cost 2 (the worst ZNCC
// cost), valid 0 and family kNoFamily.
struct PlaneSweepResult {
  cv::Mat depth_m;     // CV_32F, camera-frame z of the reference, metres; 0 = no depth
  cv::Mat confidence;  // CV_32F in [0, 1]: 1 − best cost / second-best local minimum's cost
  cv::Mat cost;        // CV_32F, the winning plane's aggregated cost (1 − ZNCC), refined by the parabola
  cv::Mat valid;       // CV_8UC1, 255 where depth_m holds a depth
  cv::Mat family;      // CV_8UC1, the winning sweep direction (0 fronto-parallel, k: extra normal k − 1)
  DepthRange range;    // the depths swept
};

// The depth range where the reference's optical axis and its neighbours' come closest: the point nearest to
// all their optical axes (least squares), its depth z in the reference, and [z / factor, z · factor].
// Nothing when the axes are (nearly) parallel, or the point lies behind the reference camera.
std::optional<DepthRange> DepthRangeFromCameras(const PlaneSweepView& reference,
                                                const std::vector<PlaneSweepView>& neighbours, double factor);

// The plane sweep. Stateless apart from its options: Compute may be called from several threads at once; it
// runs its planes in parallel on TBB's workers.
class PlaneSweepDepth {
 public:
  // Checks the options (throws InvalidOption).
  explicit PlaneSweepDepth(const PlaneSweepOptions& options);

  const PlaneSweepOptions& options() const { return options_; }

  // Depth of `reference` from `neighbours` (at least one), over the fronto-parallel planes and one more
  // family of planes per direction (its normal either sign; without offsets it is turned towards the side
  // of the reference camera most of its image looks at). A family scores a pixel only where its planes put
  // the pixel within the depth range, in front of the camera, with the ray at least slightly off the
  // planes; the lowest refined cost among the families that give a valid depth wins. Throws
  // std::invalid_argument naming the problem: an empty or non-CV_8UC1 image, a K that is not upper
  // triangular with last row 0 0 1 and positive focal lengths, a zero normal, offsets with the camera
  // between them, or no depth range (none in the options and none from the cameras).
  PlaneSweepResult Compute(const PlaneSweepView& reference, const std::vector<PlaneSweepView>& neighbours,
                           const std::vector<SweepDirection>& directions = {}) const;

 private:
  PlaneSweepOptions options_;
};

}  // namespace semap
