#include "engine/depth/stereo_sweep.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "engine/depth/frame_sweep.h"

namespace semap {
namespace {

cv::Mat Grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

// A neighbour's motion as the reference's rays see it: cam_from_ref = [R | t].
struct RelativeMotion {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
};

std::vector<RelativeMotion> Motions(const Frame& frame) {
  const Pose3d world_from_ref = frame.world_from_cam.value_or(Pose3d::Identity());
  std::vector<RelativeMotion> motions;
  motions.reserve(frame.neighbour_views.size());
  for (const CalibratedView& view : frame.neighbour_views) {
    const Pose3d cam_from_ref = view.world_from_cam.inverse() * world_from_ref;
    motions.push_back({cam_from_ref.linear(), cam_from_ref.translation()});
  }
  return motions;
}

// |∂(u, v)/∂w| of the point at inverse depth w on the normalised ray (x, y, 1) in a neighbour of focal
// lengths (fx, fy): with a = R·(x, y, 1), the point projects to f·(a_xy + t_xy·w) / (a_z + t_z·w), whose
// derivative in w is f·(t_xy·a_z − a_xy·t_z) / (a_z + t_z·w)².
double ParallaxPxM(const RelativeMotion& m, const Eigen::Vector3d& ray, double w, double fx, double fy) {
  const Eigen::Vector3d a = m.R * ray;
  const double denominator = a.z() + m.t.z() * w;
  if (!(denominator > 0.0)) return 0.0;  // behind the neighbour
  const double du = fx * (m.t.x() * a.z() - a.x() * m.t.z());
  const double dv = fy * (m.t.y() * a.z() - a.y() * m.t.z());
  return std::hypot(du, dv) / (denominator * denominator);
}

}  // namespace

CalibratedView RightView(const Frame& frame) {
  CalibratedView view = FrameCamera(frame);
  view.frame_id = frame.id;
  view.image = Grey(frame.right);
  view.world_from_cam.translation() +=
      view.world_from_cam.linear() * Eigen::Vector3d(frame.calibration.baseline_m, 0.0, 0.0);
  return view;
}

PastFrameViews::PastFrameViews(int past_frames) : past_frames_(past_frames) {}

void PastFrameViews::Attach(Frame* frame) {
  if (frame->right.empty() || !frame->world_from_cam || past_frames_ <= 0) return;
  frame->neighbour_views.push_back(RightView(*frame));
  frame->neighbour_views.insert(frame->neighbour_views.end(), views_.begin(), views_.end());
  views_.push_front(ReferenceView(*frame, 1.0));
  if (static_cast<int>(views_.size()) > past_frames_) views_.pop_back();
}

cv::Mat SweepParallax(const Frame& frame, const cv::Mat& inverse_depth_per_m, int best_views) {
  const StereoCalibration& c = frame.calibration;
  const std::vector<RelativeMotion> motions = Motions(frame);
  const std::size_t kept =
      best_views > 0 ? std::min<std::size_t>(best_views, motions.size()) : motions.size();
  cv::Mat parallax = cv::Mat::zeros(frame.left.size(), CV_32F);
  if (kept == 0) return parallax;
  std::vector<double> each(motions.size());
  for (int v = 0; v < parallax.rows; ++v) {
    const float* w = inverse_depth_per_m.ptr<float>(v);
    float* out = parallax.ptr<float>(v);
    for (int u = 0; u < parallax.cols; ++u) {
      const Eigen::Vector3d ray((u - c.cx_px) / c.fx_px, (v - c.cy_px) / c.fy_px, 1.0);
      for (std::size_t j = 0; j < motions.size(); ++j) {
        const Eigen::Matrix3d& K = frame.neighbour_views[j].K;
        each[j] = ParallaxPxM(motions[j], ray, w[u], K(0, 0), K(1, 1));
      }
      std::partial_sort(each.begin(), each.begin() + kept, each.end(), std::greater<>());
      out[u] = static_cast<float>(std::accumulate(each.begin(), each.begin() + kept, 0.0) / kept);
    }
  }
  return parallax;
}

DisparityResult CombineStereoAndSweep(const Frame& frame, const DisparityResult& sgbm,
                                      const DisparityResult& swept, const PlaneSweepOptions& options,
                                      StereoSweepCounts* counts) {
  const StereoCalibration& c = frame.calibration;
  const double focal_baseline_px_m = c.fx_px * c.baseline_m;
  cv::Mat inverse_depth_per_m = swept.disparity_px / focal_baseline_px_m;  // the sweep's 1/z, 0 without
  const cv::Mat parallax = SweepParallax(frame, inverse_depth_per_m, options.best_views);
  const double min_parallax = options.stereo_parallax_gain * focal_baseline_px_m;
  const double nearest_sgbm_disparity_px = focal_baseline_px_m / options.stereo_min_depth_m;
  DisparityResult out{sgbm.disparity_px.clone(), sgbm.confidence.clone(), sgbm.rows_aligned_px};
  StereoSweepCounts n;
  for (int v = 0; v < out.disparity_px.rows; ++v) {
    const float* sw = swept.disparity_px.ptr<float>(v);
    const float* p = parallax.ptr<float>(v);
    float* d = out.disparity_px.ptr<float>(v);
    float* conf = out.confidence.ptr<float>(v);
    const double offset_px = frame.disparity_offset.At(v, c);
    for (int u = 0; u < out.disparity_px.cols; ++u) {
      if (!(d[u] > 0.0f)) continue;                  // no SGBM depth: the sweep does not fill in
      const double measured_px = sw[u] - offset_px;  // what the pair would have measured there
      const bool near = d[u] + offset_px > nearest_sgbm_disparity_px;
      const bool disagrees = options.stereo_max_disagreement_px >= 0.0 &&
                             std::abs(measured_px - d[u]) > options.stereo_max_disagreement_px;
      if (!(sw[u] > 0.0f) || !(measured_px > 0.0) || p[u] < min_parallax || near || disagrees) {
        ++n.sgbm;
        continue;
      }
      ++n.replaced;
      d[u] = static_cast<float>(measured_px);
      conf[u] = 1.0f;
    }
  }
  if (counts != nullptr) counts->Add(n);
  return out;
}

PlaneSweepOptions StereoFrameSweepOptions(const PlaneSweepOptions& options) {
  PlaneSweepOptions o = options;
  o.min_depth_m = options.stereo_min_depth_m;
  o.max_depth_m = options.stereo_max_depth_m;
  o.window_px = options.stereo_window_px;
  o.best_views = options.stereo_best_views;
  o.label_directions = false;
  return o;
}

DisparityResult StereoSweepDisparity(const Frame& frame, const StereoDepth& stereo,
                                     const PlaneSweepDepth& stereo_sweep, StereoSweepCounts* counts) {
  DisparityResult sgbm =
      stereo.Compute(frame.left, frame.right, frame.row_offsets ? &*frame.row_offsets : nullptr);
  // The right view alone is the pair SGBM has matched: sweep only with earlier frames beside it.
  if (frame.neighbour_views.size() < 2) return sgbm;
  const DisparityResult swept = SweepFrameDisparity(frame, stereo_sweep, stereo.options().half_resolution);
  return CombineStereoAndSweep(frame, sgbm, swept, stereo_sweep.options(), counts);
}

}  // namespace semap
