#include "engine/odometry/internal/stereo_pose_refiner.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace semap::odometry_internal {
namespace {

using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Vector8 = Eigen::Matrix<double, 8, 1>;
using Matrix8 = Eigen::Matrix<double, 8, 8>;

// A point closer than this to the camera plane is not projected (behind or at the camera), m.
constexpr double kMinDepthM = 1e-3;
// A step smaller than this (norm of the 6- or 7-vector, m, rad and px) ends the Gauss-Newton steps.
constexpr double kConvergedStep = 1e-10;
// Half-width of the central difference that gives the residuals' derivative by each term of the disparity
// offset, px.
constexpr double kOffsetStepPx = 1e-3;
// An offset term's information left after the pose (and the other term) is marginalised, below this share of
// its own, is none: the term is not observable (rounding), and its standard deviation infinite.
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
  out.residual_px << c.fx_px * p.x() * inv_z + c.cx_px - left_px.x(),
      c.fy_px * p.y() * inv_z + c.cy_px - left_px.y(),
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
// (v, w) of cur_from_ref: cur_from_ref <- [Exp(w) | v] cur_from_ref, and (columns 7 and 8, filled by the
// caller when the offset is estimated) to the offset's terms.
struct MatchResiduals {
  Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 8> j = Eigen::Matrix<double, 6, 8>::Zero();
  int rows = 0;
  double max_abs_px() const { return rows == 0 ? 0.0 : r.head(rows).cwiseAbs().maxCoeff(); }
};

// Which sides of a match are triangulated is decided on the measured disparities (min_disparity_px), so
// that the rows do not change with the offset.
// A side's offset is taken at its left pixel's row, in the frame that triangulates and in the frame that
// sees the point.
MatchResiduals Residuals(const StereoCalibration& c, const StereoMatch& m, const Pose3d& cur_from_ref,
                         double min_disparity_px, const DisparityOffset& offset) {
  MatchResiduals out;
  const double ref_offset_px = offset.At(m.ref_left_px.y(), c);
  const double cur_offset_px = offset.At(m.cur_left_px.y(), c);
  // The reference frame's point, seen in the current frame.
  if (m.ref_left_px.x() - m.ref_right_u_px >= min_disparity_px &&
      m.ref_left_px.x() - m.ref_right_u_px + ref_offset_px > 0.0) {
    const Eigen::Vector3d p = cur_from_ref * Triangulate(c, m.ref_left_px, m.ref_right_u_px, ref_offset_px);
    if (p.z() > kMinDepthM) {
      const Projection proj = Project(c, p, m.cur_left_px, m.cur_right_u_px, cur_offset_px);
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
      m.cur_left_px.x() - m.cur_right_u_px + cur_offset_px > 0.0) {
    const Eigen::Vector3d x_cur = Triangulate(c, m.cur_left_px, m.cur_right_u_px, cur_offset_px);
    const Pose3d ref_from_cur = cur_from_ref.inverse();
    const Eigen::Vector3d q = ref_from_cur * x_cur;
    if (q.z() > kMinDepthM) {
      const Projection proj = Project(c, q, m.ref_left_px, m.ref_right_u_px, ref_offset_px);
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

// The offset with `delta` added to its term `term` (0 constant, 1 per row).
DisparityOffset Shifted(DisparityOffset offset, int term, double delta) {
  (term == 0 ? offset.constant_px : offset.per_row_px) += delta;
  return offset;
}

// The residuals with their derivatives by the first `terms` terms of the offset in columns 7 and 8 (central
// differences).
MatchResiduals ResidualsWithOffset(const StereoCalibration& c, const StereoMatch& m,
                                   const Pose3d& cur_from_ref, double min_disparity_px,
                                   const DisparityOffset& offset, int terms) {
  MatchResiduals out = Residuals(c, m, cur_from_ref, min_disparity_px, offset);
  if (out.rows == 0) return out;
  for (int t = 0; t < terms; ++t) {
    const MatchResiduals plus =
        Residuals(c, m, cur_from_ref, min_disparity_px, Shifted(offset, t, kOffsetStepPx));
    const MatchResiduals minus =
        Residuals(c, m, cur_from_ref, min_disparity_px, Shifted(offset, t, -kOffsetStepPx));
    if (plus.rows != out.rows || minus.rows != out.rows) continue;  // a side at its limit: no derivative
    out.j.col(6 + t).head(out.rows) =
        (plus.r.head(out.rows) - minus.r.head(out.rows)) / (2.0 * kOffsetStepPx);
  }
  return out;
}

// The information of term `t` of a 2×2 information matrix with the other term marginalised (when it has any).
double MarginalInformation(const Eigen::Matrix2d& info, int t) {
  const int other = 1 - t;
  return info(other, other) > 0.0 ? info(t, t) - info(t, other) * info(t, other) / info(other, other)
                                  : info(t, t);
}

// The information on the first `terms` offset terms (entries 7 and 8 of the normal matrix `h`) left once the
// pose is marginalised: their Schur complement. A term whose information, with the other term marginalised
// too, falls below kMinOffsetInformationShare of its own entry (or is not finite) has none: its row and
// column are zero.
Eigen::Matrix2d OffsetInformation(const Matrix8& h, int terms) {
  Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
  if (terms == 0) return info;
  const Eigen::Matrix<double, 6, 6> hpp = h.topLeftCorner<6, 6>();
  const Eigen::MatrixXd hpo = h.block(0, 6, 6, terms);
  const Eigen::MatrixXd schur = h.block(6, 6, terms, terms) - hpo.transpose() * hpp.ldlt().solve(hpo);
  info.topLeftCorner(terms, terms) = schur;
  const Eigen::Matrix2d full = info;
  for (int t = 0; t < terms; ++t) {
    const double own = MarginalInformation(full, t);
    if (!std::isfinite(own) || !(own > kMinOffsetInformationShare * h(6 + t, 6 + t))) {
      info.row(t).setZero();
      info.col(t).setZero();
    }
  }
  return info;
}

}  // namespace

RefinedMotion RefineStereoMotion(const StereoCalibration& calibration,
                                 const std::vector<StereoMatch>& matches, const Pose3d& cur_from_ref,
                                 const std::vector<bool>& start_inliers, const RefinerOptions& options) {
  RefinedMotion out;
  out.cur_from_ref = cur_from_ref;
  out.disparity_offset = options.disparity_offset;
  const int terms = std::clamp(options.estimate_offset_terms, 0, 2);
  Matrix8 last_h = Matrix8::Zero();
  out.inliers = start_inliers;
  out.inliers.resize(matches.size(), false);
  for (int round = 0; round < options.rounds; ++round) {
    for (int it = 0; it < options.iterations; ++it) {
      Matrix8 h = Matrix8::Zero();
      Vector8 g = Vector8::Zero();
      int used = 0;
      for (size_t i = 0; i < matches.size(); ++i) {
        if (!out.inliers[i]) continue;
        const MatchResiduals res = ResidualsWithOffset(calibration, matches[i], out.cur_from_ref,
                                                       options.min_disparity_px, out.disparity_offset, terms);
        for (int k = 0; k < res.rows; ++k) {
          const double a = std::abs(res.r(k));
          const double w = a <= options.huber_px ? 1.0 : options.huber_px / a;
          const Vector8 jk = res.j.row(k).transpose();
          h.noalias() += w * jk * jk.transpose();
          g.noalias() += w * jk * res.r(k);
        }
        used += res.rows > 0;
      }
      if (used < 3) break;  // too few to constrain six unknowns: keep the start
      // An offset term is an unknown only where the matches tell it (OffsetInformation); the others stay.
      const Eigen::Matrix2d info = OffsetInformation(h, terms);
      std::vector<int> index = {0, 1, 2, 3, 4, 5};
      for (int t = 0; t < terms; ++t) {
        if (info(t, t) > 0.0) index.push_back(6 + t);
      }
      const int n = static_cast<int>(index.size());
      Eigen::MatrixXd hs(n, n);
      Eigen::VectorXd gs(n);
      for (int a = 0; a < n; ++a) {
        gs(a) = g(index[a]);
        for (int b = 0; b < n; ++b) hs(a, b) = h(index[a], index[b]);
      }
      const Eigen::VectorXd solved = -hs.ldlt().solve(gs);
      if (!solved.allFinite()) break;
      Vector8 step = Vector8::Zero();
      for (int a = 0; a < n; ++a) step(index[a]) = solved(a);
      last_h = h;
      Pose3d delta = Pose3d::Identity();
      const double angle = step.segment<3>(3).norm();
      if (angle > 0.0)
        delta.linear() = Eigen::AngleAxisd(angle, step.segment<3>(3) / angle).toRotationMatrix();
      delta.translation() = step.head<3>();
      out.cur_from_ref = delta * out.cur_from_ref;
      out.disparity_offset.constant_px += step(6);
      out.disparity_offset.per_row_px += step(7);
      if (step.norm() < kConvergedStep) break;
    }
    // Inliers: every match (not only the last round's) whose largest residual is below the threshold.
    out.num_inliers = 0;
    double sum_sq = 0.0;
    int rows = 0;
    for (size_t i = 0; i < matches.size(); ++i) {
      const MatchResiduals res = Residuals(calibration, matches[i], out.cur_from_ref,
                                           options.min_disparity_px, out.disparity_offset);
      out.inliers[i] = res.rows > 0 && res.max_abs_px() <= options.inlier_threshold_px;
      if (out.inliers[i]) {
        ++out.num_inliers;
        sum_sq += res.r.head(res.rows).squaredNorm();
        rows += res.rows;
      }
    }
    out.rms_px = rows > 0 ? std::sqrt(sum_sq / rows) : 0.0;
  }
  if (terms > 0) {
    // The terms' information with the pose marginalised, in units of the residuals' variance (the
    // Gauss-Newton normal matrix holds it per unit weight). No information (no motion, or only a rotation:
    // the depths do not change with it): infinite standard deviation.
    const double variance = out.rms_px * out.rms_px;
    const Eigen::Matrix2d info = OffsetInformation(last_h, terms);
    out.offset_information = out.num_inliers > 0 && variance > 0.0 ? Eigen::Matrix2d(info / variance) : info;
    const double own = MarginalInformation(info, 0);
    out.disparity_offset_sigma_px = own > 0.0 && out.num_inliers > 0
                                        ? out.rms_px / std::sqrt(own)
                                        : std::numeric_limits<double>::infinity();
  }
  return out;
}

}  // namespace semap::odometry_internal
