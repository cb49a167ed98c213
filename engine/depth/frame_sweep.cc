#include "engine/depth/frame_sweep.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace semap {
namespace {

// Pixel (u, v) of an image resampled by `scale` (area-averaged) sees what (u + ½) / scale − ½ saw: the
// principal point moves with the pixel centres, the focal lengths scale.
Eigen::Matrix3d ScaledK(Eigen::Matrix3d K, double scale) {
  if (scale == 1.0) return K;
  K.row(0) *= scale;
  K.row(1) *= scale;
  K(0, 2) += 0.5 * scale - 0.5;
  K(1, 2) += 0.5 * scale - 0.5;
  return K;
}

cv::Mat Grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

cv::Mat Resampled(const cv::Mat& image, double scale) {
  if (scale == 1.0) return image;
  cv::Mat out;
  cv::resize(image, out, cv::Size(), scale, scale, cv::INTER_AREA);
  return out;
}

}  // namespace

PlaneSweepView FrameCamera(const Frame& frame) {
  const StereoCalibration& c = frame.calibration;
  PlaneSweepView view;
  view.frame_id = frame.id;
  view.K << c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0;
  view.world_from_cam = frame.world_from_cam.value_or(Pose3d::Identity());
  return view;
}

PlaneSweepView ReferenceView(const Frame& frame, double scale) {
  PlaneSweepView view = FrameCamera(frame);
  view.image = Resampled(Grey(frame.left), scale);
  view.K = ScaledK(view.K, scale);
  return view;
}

PlaneSweepView ScaledView(const CalibratedView& view, double scale) {
  PlaneSweepView out = view;
  out.image = Resampled(view.image, scale);
  out.K = ScaledK(view.K, scale);
  return out;
}

DisparityResult SweepFrameDisparity(const Frame& frame, const PlaneSweepDepth& sweep, bool half_resolution,
                                    const std::vector<SweepDirection>& directions) {
  const std::string name = "frame " + std::to_string(frame.id);
  if (frame.neighbour_views.empty()) {
    throw std::invalid_argument(name + ": no right image and no neighbour views to sweep its depth against");
  }
  if (!frame.world_from_cam) throw std::invalid_argument(name + ": the plane sweep needs the frame's pose");
  if (!(frame.calibration.baseline_m > 0.0)) {
    throw std::invalid_argument(name +
                                ": the calibration's baseline (to the nearest neighbour view) is not > 0");
  }
  const double scale = half_resolution ? 0.5 : 1.0;
  const PlaneSweepView reference = ReferenceView(frame, scale);
  std::vector<PlaneSweepView> neighbours;
  neighbours.reserve(frame.neighbour_views.size());
  for (const CalibratedView& view : frame.neighbour_views) neighbours.push_back(ScaledView(view, scale));
  const PlaneSweepResult swept = sweep.Compute(reference, neighbours, directions);

  cv::Mat depth_m = swept.depth_m;
  if (depth_m.size() != frame.left.size()) {
    cv::resize(swept.depth_m, depth_m, frame.left.size(), 0.0, 0.0, cv::INTER_NEAREST);
  }
  const double focal_baseline_px_m = frame.calibration.fx_px * frame.calibration.baseline_m;
  DisparityResult result;
  result.disparity_px = cv::Mat::zeros(depth_m.size(), CV_32F);
  result.confidence = cv::Mat::zeros(depth_m.size(), CV_32F);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_m.ptr<float>(v);
    float* d = result.disparity_px.ptr<float>(v);
    float* c = result.confidence.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!(z[u] > 0.0f)) continue;
      d[u] = static_cast<float>(focal_baseline_px_m / z[u]);
      c[u] = 1.0f;
    }
  }
  return result;
}

}  // namespace semap
