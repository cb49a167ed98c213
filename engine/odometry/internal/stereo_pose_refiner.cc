#include "engine/odometry/internal/stereo_pose_refiner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace semap::odometry_internal {
namespace {

using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Vector7 = Eigen::Matrix<double, 7, 1>;
using Matrix7 = Eigen::Matrix<double, 7, 7>;

// A point closer than this to the camera plane is not projected (behind or at the camera), m.
constexpr double kMinDepthM = 1e-3;
// A step smaller than this (norm of the 6- or 7-vector, m, rad and px) ends the Gauss-Newton steps.
constexpr double kConvergedStep = 1e-10;
// Half-width of the central difference that gives the residuals' derivative by the disparity offset, px.
constexpr double kOffsetStepPx = 1e-3;
// The offset's information left after the pose is marginalised, below this share of its own, is none: the
// offset is not observable (rounding), and its standard deviation infinite.
constexpr double kMinOffsetInformationShare = 1e-9;

Eigen::Matrix3d Skew(const Eigen::Vector3d& p) {
  Eigen::Matrix3d s;
  s << 0.0, -p.z(), p.y(), p.z(), 0.0, -p.x(), -p.y(), p.x(), 0.0;
  return s;
}

// Residuals (u_left, v_left, u_right) of the point `p` (camera frame) against the observation, and their
// derivatives with respect to p.
struct Projection {
  Eigen::Vector3d residual_px;
  Eigen::Matrix3d d_residual_d_p;
};

Projection Project(const StereoCalibration& c, const Eigen::Vector3d& p, const Eigen::Vector2d& left_px,
                   double right_u_px, double disparity_offset_px) {
  const double inv_z = 1.0 / p.z();
  Projection out;
  out.residual_px << c.fx_px * p.x() * inv_z + c.cx_px - left_px.x(), c.fy_px * p.y() * inv_z + c.cy_px - left_px.y(),
      c.fx_px * (p.x() - c.baseline_m) * inv_z + c.cx_px + disparity_offset_px - right_u_px;
  out.d_residual_d_p << c.fx_px * inv_z, 0.0, -c.fx_px * p.x() * inv_z * inv_z,  //
      0.0, c.fy_px * inv_z, -c.fy_px * p.y() * inv_z * inv_z,                    //
      c.fx_px * inv_z, 0.0, -c.fx_px * (p.x() - c.baseline_m) * inv_z * inv_z;
  return out;
}

// The measured disparity (left u − right u) is the true one minus the offset.
Eigen::Vector3d Triangulate(const StereoCalibration& c, const Eigen::Vector2d& left_px, double right_u_px,
                            double disparity_offset_px) {
  return c.Unproject(left_px.x(), left_px.y(),
                     c.DepthFromDisparity(left_px.x() - right_u_px + disparity_offset_px));
}

// One match's residual rows (up to 6) and their Jacobians with respect to a left perturbation
// (v, w) of cur_from_ref: cur_from_ref <- [Exp(w) | v] cur_from_ref, and (column 7, filled by the caller
// when the offset is estimated) to the disparity offset.
struct MatchResiduals {
  Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 7> j = Eigen::Matrix<double, 6, 7>::Zero();
  int rows = 0;
  double max_abs_px() const { return rows == 0 ? 0.0 : r.head(rows).cwiseAbs().maxCoeff(); }
};

// Which sides of a match are triangulated is decided on the measured disparities (min_disparity_px), so
// that the rows do not change with the offset.
MatchResiduals Residuals(const StereoCalibration& c, const StereoMatch& m, const Pose3d& cur_from_ref,
                         double min_disparity_px, double offset_px) {
  MatchResiduals out;
  // The reference frame's point, seen in the current frame.
  if (m.ref_left_px.x() - m.ref_right_u_px >= min_disparity_px &&
      m.ref_left_px.x() - m.ref_right_u_px + offset_px > 0.0) {
    const Eigen::Vector3d p = cur_from_ref * Triangulate(c, m.ref_left_px, m.ref_right_u_px, offset_px);
    if (p.z() > kMinDepthM) {
      const Projection proj = Project(c, p, m.cur_left_px, m.cur_right_u_px, offset_px);
      Matrix36 dp;
      dp << Eigen::Matrix3d::Identity(), -Skew(p);
      const int n = m.has_current_right ? 3 : 2;
      out.r.segment(out.rows, n) = proj.residual_px.head(n);
      out.j.block(out.rows, 0, n, 6) = (proj.d_residual_d_p * dp).topRows(n);
      out.rows += n;
    }
  }
  // The current frame's point, seen in the reference frame.
  if (m.has_current_right && m.cur_left_px.x() - m.cur_right_u_px >= min_disparity_px &&
      m.cur_left_px.x() - m.cur_right_u_px + offset_px > 0.0) {
    const Eigen::Vector3d x_cur = Triangulate(c, m.cur_left_px, m.cur_right_u_px, offset_px);
    const Pose3d ref_from_cur = cur_from_ref.inverse();
    const Eigen::Vector3d q = ref_from_cur * x_cur;
    if (q.z() > kMinDepthM) {
      const Projection proj = Project(c, q, m.ref_left_px, m.ref_right_u_px, offset_px);
      const Eigen::Matrix3d rt = ref_from_cur.linear();
      Matrix36 dq;
      dq << -rt, rt * Skew(x_cur);
      out.r.segment(out.rows, 3) = proj.residual_px;
      out.j.block(out.rows, 0, 3, 6) = proj.d_residual_d_p * dq;
      out.rows += 3;
    }
  }
  return out;
}

// The residuals with their derivative by the offset in column 7 (central difference) when `estimate`.
MatchResiduals ResidualsWithOffset(const StereoCalibration& c, const StereoMatch& m, const Pose3d& cur_from_ref,
                                   double min_disparity_px, double offset_px, bool estimate) {
  MatchResiduals out = Residuals(c, m, cur_from_ref, min_disparity_px, offset_px);
  if (!estimate || out.rows == 0) return out;
  const MatchResiduals plus = Residuals(c, m, cur_from_ref, min_disparity_px, offset_px + kOffsetStepPx);
  const MatchResiduals minus = Residuals(c, m, cur_from_ref, min_disparity_px, offset_px - kOffsetStepPx);
  if (plus.rows != out.rows || minus.rows != out.rows) return out;  // a side at its limit: no derivative
  out.j.col(6).head(out.rows) = (plus.r.head(out.rows) - minus.r.head(out.rows)) / (2.0 * kOffsetStepPx);
  return out;
}

// The information on the offset (entry 7 of the normal matrix `h`) left once the pose is marginalised: its
// Schur complement; 0 when that is below kMinOffsetInformationShare of the entry itself or not finite.
double OffsetInformation(const Matrix7& h) {
  const double alone = h(6, 6);
  const double info = alone - h.block<1, 6>(6, 0) * h.topLeftCorner<6, 6>().ldlt().solve(h.block<6, 1>(0, 6));
  return std::isfinite(info) && info > kMinOffsetInformationShare * alone ? info : 0.0;
}

}  // namespace

RefinedMotion RefineStereoMotion(const StereoCalibration& calibration, const std::vector<StereoMatch>& matches,
                                 const Pose3d& cur_from_ref, const std::vector<bool>& start_inliers,
                                 const RefinerOptions& options) {
  RefinedMotion out;
  out.cur_from_ref = cur_from_ref;
  out.disparity_offset_px = options.disparity_offset_px;
  const bool estimate = options.estimate_disparity_offset;
  const int unknowns = estimate ? 7 : 6;
  Matrix7 last_h = Matrix7::Zero();
  out.inliers = start_inliers;
  out.inliers.resize(matches.size(), false);
  for (int round = 0; round < options.rounds; ++round) {
    for (int it = 0; it < options.iterations; ++it) {
      Matrix7 h = Matrix7::Zero();
      Vector7 g = Vector7::Zero();
      int used = 0;
      for (size_t i = 0; i < matches.size(); ++i) {
        if (!out.inliers[i]) continue;
        const MatchResiduals res = ResidualsWithOffset(calibration, matches[i], out.cur_from_ref,
                                                       options.min_disparity_px, out.disparity_offset_px, estimate);
        for (int k = 0; k < res.rows; ++k) {
          const double a = std::abs(res.r(k));
          const double w = a <= options.huber_px ? 1.0 : options.huber_px / a;
          const Vector7 jk = res.j.row(k).transpose();
          h.noalias() += w * jk * jk.transpose();
          g.noalias() += w * jk * res.r(k);
        }
        used += res.rows > 0;
      }
      if (used < 3) break;  // too few to constrain six unknowns: keep the start
      // The offset is a seventh unknown only where the matches tell it (see OffsetInformation).
      const int solved = unknowns == 7 && OffsetInformation(h) > 0.0 ? 7 : 6;
      Vector7 step = Vector7::Zero();
      step.head(solved) = -h.topLeftCorner(solved, solved).ldlt().solve(g.head(solved));
      if (!step.allFinite()) break;
      last_h = h;
      Pose3d delta = Pose3d::Identity();
      const double angle = step.segment<3>(3).norm();
      if (angle > 0.0) delta.linear() = Eigen::AngleAxisd(angle, step.segment<3>(3) / angle).toRotationMatrix();
      delta.translation() = step.head<3>();
      out.cur_from_ref = delta * out.cur_from_ref;
      out.disparity_offset_px += step(6);
      if (step.norm() < kConvergedStep) break;
    }
    // Inliers: every match (not only the last round's) whose largest residual is below the threshold.
    out.num_inliers = 0;
    double sum_sq = 0.0;
    int rows = 0;
    for (size_t i = 0; i < matches.size(); ++i) {
      const MatchResiduals res =
          Residuals(calibration, matches[i], out.cur_from_ref, options.min_disparity_px, out.disparity_offset_px);
      out.inliers[i] = res.rows > 0 && res.max_abs_px() <= options.inlier_threshold_px;
      if (out.inliers[i]) {
        ++out.num_inliers;
        sum_sq += res.r.head(res.rows).squaredNorm();
        rows += res.rows;
      }
    }
    out.rms_px = rows > 0 ? std::sqrt(sum_sq / rows) : 0.0;
  }
  if (estimate) {
    // The offset's variance: the inverse of its information with the pose marginalised (the Schur
    // complement of the pose block), scaled by the residuals' variance. No information left (no motion, or
    // only a rotation: the depths do not change with it): infinite.
    const double info = OffsetInformation(last_h);
    out.disparity_offset_sigma_px = info > 0.0 && out.num_inliers > 0 ? out.rms_px / std::sqrt(info)
                                                                      : std::numeric_limits<double>::infinity();
  }
  return out;
}

}  // namespace semap::odometry_internal
