// Sparse points of a calibrated multi-view set from its own cameras (bench/fountain_checks.cc): keypoint
// matches between pairs of views joined into tracks, each track triangulated with the known cameras and kept
// when every view sees it in front and within a reprojection bound. Not API: bench helpers.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "engine/core/calibration.h"

namespace semap::bench {

// A pinhole camera without distortion: a world point X projects to x ~ K · cam_from_world · X.
struct PinholeCamera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Pose3d world_from_cam = Pose3d::Identity();
};

// The camera-frame point of world point `p_world`.
Eigen::Vector3d InCamera(const PinholeCamera& camera, const Eigen::Vector3d& p_world);

// The pixel of world point `p_world`; requires it in front of the camera.
Eigen::Vector2d ProjectPx(const PinholeCamera& camera, const Eigen::Vector3d& p_world);

// The fundamental matrix F of the pair (a, b): a pixel x_a of a and its match x_b of b satisfy
// x̃_bᵀ F x̃_a = 0.
Eigen::Matrix3d FundamentalMatrix(const PinholeCamera& a, const PinholeCamera& b);

// Distance (px) of `x_b_px` from the epipolar line F x̃_a in b.
double EpipolarDistancePx(const Eigen::Matrix3d& F, const Eigen::Vector2d& x_a_px,
                          const Eigen::Vector2d& x_b_px);

// One keypoint of one view.
struct ViewKeypoint {
  int view = 0;
  int keypoint = 0;
  bool operator==(const ViewKeypoint&) const = default;
};

// A match of two keypoints in two different views.
struct KeypointMatch {
  ViewKeypoint a, b;
};

// The tracks the matches join (connected keypoints, union-find), each sorted by view, with at least
// `min_views` keypoints. A track holding two keypoints of one view is ambiguous and left out.
std::vector<std::vector<ViewKeypoint>> BuildTracks(const std::vector<KeypointMatch>& matches, int min_views);

// One observation of a point: the view's camera and the pixel where it is seen.
struct Observation {
  PinholeCamera camera;
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();
};

// The point seen by the observations by linear DLT (each observation's rows in normalised image coordinates
// K⁻¹ x̃, each row scaled to unit length); nothing with fewer than two observations or when the solution lies
// at infinity.
std::optional<Eigen::Vector3d> TriangulateLinear(const std::vector<Observation>& observations);

// `p_world` moved by `iterations` Gauss–Newton steps on the sum of the squared reprojection errors (px).
Eigen::Vector3d RefineReprojection(const std::vector<Observation>& observations, Eigen::Vector3d p_world,
                                   int iterations);

// The reprojection error (px) of `p_world` in each observation; infinite where it lies behind the camera.
std::vector<double> ReprojectionErrorsPx(const std::vector<Observation>& observations,
                                         const Eigen::Vector3d& p_world);

// TriangulateLinear, then RefineReprojection; kept when the point lies in front of every camera with every
// reprojection error below `max_error_px`.
std::optional<Eigen::Vector3d> TriangulateTrack(const std::vector<Observation>& observations,
                                                double max_error_px, int iterations = 5);

}  // namespace semap::bench
