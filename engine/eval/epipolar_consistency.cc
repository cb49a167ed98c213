#include "engine/eval/epipolar_consistency.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "engine/core/check.h"

namespace semap {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

Eigen::Matrix3d Skew(const Eigen::Vector3d& t) {
  Eigen::Matrix3d s;
  s << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
  return s;
}

Eigen::Matrix3d Intrinsics(const StereoCalibration& k) {
  Eigen::Matrix3d m;
  m << k.fx_px, 0.0, k.cx_px, 0.0, k.fy_px, k.cy_px, 0.0, 0.0, 1.0;
  return m;
}

// The fundamental matrix of the motion b_from_a = (R, t).
Eigen::Matrix3d Fundamental(const Eigen::Matrix3d& k_inverse, const Eigen::Matrix3d& r,
                            const Eigen::Vector3d& t) {
  return k_inverse.transpose() * Skew(t) * r * k_inverse;
}

double Sampson(const Eigen::Matrix3d& f, const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px) {
  const Eigen::Vector3d xa(a_px.x(), a_px.y(), 1.0), xb(b_px.x(), b_px.y(), 1.0);
  const Eigen::Vector3d fa = f * xa, fb = f.transpose() * xb;
  const double denominator = fa.x() * fa.x() + fa.y() * fa.y() + fb.x() * fb.x() + fb.y() * fb.y();
  if (!(denominator > 0.0)) return 0.0;
  return std::abs(xb.dot(fa)) / std::sqrt(denominator);
}

Eigen::Matrix3d FromRotationVectorDeg(const Eigen::Vector3d& angles_deg) {
  const double angle = angles_deg.norm() * kDegToRad;
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, angles_deg.normalized()).toRotationMatrix();
}

}  // namespace

double SampsonDistancePx(const StereoCalibration& intrinsics, const Pose3d& b_from_a,
                         const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px) {
  const Eigen::Matrix3d k_inverse = Intrinsics(intrinsics).inverse();
  return Sampson(Fundamental(k_inverse, b_from_a.rotation(), b_from_a.translation()), a_px, b_px);
}

namespace {

// Calls f(distance) with the Sampson distance of every track of every window under the windows' motions seen
// from a camera frame rotated by `truth_from_image`, in order.
template <typename F>
void ForEachDistance(const std::vector<TrackWindow>& windows, const StereoCalibration& intrinsics,
                     const Eigen::Matrix3d& truth_from_image, F f) {
  const Eigen::Matrix3d k_inverse = Intrinsics(intrinsics).inverse();
  const Eigen::Matrix3d& r0 = truth_from_image;
  for (const TrackWindow& w : windows) {
    SEMAP_ASSERT(w.a_px.size() == w.b_px.size(), "a_px " << w.a_px.size() << ", b_px " << w.b_px.size());
    // The motion seen from the images' camera frame: x_b' = Rᵀ(R_ba (R x_a') + t_ba).
    const Eigen::Matrix3d fundamental = Fundamental(k_inverse, r0.transpose() * w.b_from_a.rotation() * r0,
                                                    r0.transpose() * w.b_from_a.translation());
    for (std::size_t i = 0; i < w.a_px.size(); ++i) f(Sampson(fundamental, w.a_px[i], w.b_px[i]));
  }
}

// EpipolarAgreementOf(...).mean_px without the median (the rotation fit's objective).
double CappedMeanPx(const std::vector<TrackWindow>& windows, const StereoCalibration& intrinsics,
                    const Eigen::Matrix3d& truth_from_image, double cap_px) {
  double sum = 0.0;
  std::size_t n = 0;
  ForEachDistance(windows, intrinsics, truth_from_image, [&](double d) {
    sum += std::min(d, cap_px);
    ++n;
  });
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace

EpipolarAgreement EpipolarAgreementOf(const std::vector<TrackWindow>& windows,
                                      const StereoCalibration& intrinsics,
                                      const Eigen::Matrix3d& truth_from_image, double cap_px) {
  SEMAP_ASSERT(cap_px > 0.0, "cap_px " << cap_px);
  std::vector<double> distances;
  double sum = 0.0;
  ForEachDistance(windows, intrinsics, truth_from_image, [&](double d) {
    distances.push_back(d);
    sum += std::min(d, cap_px);
  });
  EpipolarAgreement result;
  result.tracks = static_cast<int>(distances.size());
  if (distances.empty()) return result;
  result.mean_px = sum / static_cast<double>(distances.size());
  const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  result.median_px = *middle;
  return result;
}

EpipolarRotationFit FitEpipolarRotation(const std::vector<TrackWindow>& windows,
                                        const StereoCalibration& intrinsics, double cap_px,
                                        double start_step_deg, double min_step_deg) {
  SEMAP_ASSERT(cap_px > 0.0, "cap_px " << cap_px);
  SEMAP_ASSERT(start_step_deg > 0.0 && min_step_deg > 0.0,
               "steps " << start_step_deg << ", " << min_step_deg);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double best = CappedMeanPx(windows, intrinsics, Eigen::Matrix3d::Identity(), cap_px);
  for (double step = start_step_deg; step >= min_step_deg;) {
    bool improved = false;
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        Eigen::Vector3d y = x;
        y[axis] += sign * step;
        const double value = CappedMeanPx(windows, intrinsics, FromRotationVectorDeg(y), cap_px);
        if (value < best) {
          best = value;
          x = y;
          improved = true;
        }
      }
    }
    if (!improved) step /= 2.0;
  }
  EpipolarRotationFit fit;
  fit.angles_deg = x;
  fit.truth_from_image = FromRotationVectorDeg(x);
  fit.agreement = EpipolarAgreementOf(windows, intrinsics, fit.truth_from_image, cap_px);
  return fit;
}

}  // namespace semap
