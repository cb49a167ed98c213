// A live vertex's depth filter (map.visibility: depth, map.fuse_gate_sigmas > 0): the vertex is the fused
// estimate of every sighting of its surface point, not the first one.
//
// What each rule approximates:
//   - A sighting is one view's depth map read at the vertex's own pixel (1/z interpolated bilinearly between
//     the four pixels around it): the point that view saw along the ray through the vertex, x·D/z. Reading
//     the dense depth at the vertex's pixel stands in for the epipolar search of SVO/REMODE's depth filter;
//     each view gives one sighting, wherever the frame's points (a budget of ~10,000) happened to fall.
//   - Its noise is that of one stereo disparity: σ_z = z²·σ_d/(f·B) in depth, σ = σ_z·r/z along the ray,
//     at the vertex's depth z (a weight that depended on the sighting's own depth would be biased).
//     The vertex estimate is the inverse-variance mean of its sightings, Σ x_i/σ_i² / Σ 1/σ_i², with σ
//     = 1/√Σ 1/σ_i²: a Gaussian filter, isotropic in 3D. The sightings lie on different rays through
//     the current estimate, all on the surface within their noise: their mean lies on the surface too
//     (where it is locally flat), and it may slide along it by a fraction of the sightings' spread, which is
//     harmless to a mesh. The error falls as 1/√n with the sightings (tests/engine/map/depth_filter_test.cc).
//   - The gate: a sighting whose depth lies within gate_sigmas · √(σ_z² + σ²) of the vertex's depth is
//     of the vertex (an inlier). A view that saw farther than that at every pixel around the vertex's one
//     (or sky) saw through it: an outlier sighting, the evidence SVO's Beta term counts. A view that saw
//     nearer saw something in front of it (occlusion): no evidence. Where the four pixels around disagree by
//     more than the gate (a depth edge), a sighting within the gate counts as an inlier without moving the
//     vertex.
//   - Where the vertex is written: the triangulation keeps a vertex where it was inserted until its estimate
//     has left it by map.fuse_move_sigmas of its σ (a move re-triangulates its star and re-votes its cells,
//     the costly part); the output mesh follows the estimate sooner, from map.fuse_output_sigmas of its σ on,
//     with no re-triangulation: the surface's connectivity is the triangulation's, its vertices the fused
//     estimates. A vertex so moved keeps its point id, under a new output id (VertexInfo::output_version),
//     so that a mesh delta re-sends its triangles.
//   - The inlier ratio is judged by counts (IsOutlier), not by SVO's Beta posterior: a vertex that at least
//     `min_outliers` views saw through, and more saw through than saw, is an outlier (an SGBM mismatch, or
//     a moving object that left).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "engine/map/internal/depth_votes.h"

namespace semap::map_internal {

struct DepthFilter {
  double weight = 0.0;                                     // Σ 1/σ_i², 1/m²
  Eigen::Vector3d weighted_sum = Eigen::Vector3d::Zero();  // Σ x_i/σ_i²
  std::uint32_t inliers = 0;                               // views that saw the vertex
  std::uint32_t outliers = 0;                              // views that saw through it

  bool started() const { return weight > 0.0; }
  // The first sighting, at `x_world` with σ `sigma_m` along its ray.
  void Start(const Eigen::Vector3d& x_world, double sigma_m);
  // One more sighting of the vertex at `x_world`, σ `sigma_m` (counted in `inliers`).
  void AddInlier(const Eigen::Vector3d& x_world, double sigma_m);
  Eigen::Vector3d Estimate() const { return weighted_sum / weight; }
  double Sigma() const { return 1.0 / std::sqrt(weight); }
  bool IsOutlier(std::uint32_t min_outliers) const {
    return min_outliers > 0 && outliers >= min_outliers && outliers > inliers;
  }
};

enum class Sighting {
  kNone,     // outside the view, no depth there, or occluded
  kInlier,   // the view saw the vertex (its estimate updated where the view's depth is smooth there)
  kOutlier,  // the view saw through the vertex
};

// The along-ray σ of a point at camera-frame position `p_cam` of `view` (depth p_cam.z()) seen with disparity
// noise `disparity_sigma_px`.
inline double AlongRaySigma(const VotingView& view, const Eigen::Vector3d& p_cam, double disparity_sigma_px) {
  return view.DepthSigma(p_cam.z(), disparity_sigma_px) * (p_cam.norm() / p_cam.z());
}

// Adds the sighting of the vertex at `vertex_world` by `view` to `filter` (which must be started), as the
// header says. Thread-safe on distinct filters (reads the view only).
Sighting ObserveVertex(const Eigen::Vector3d& vertex_world, const VotingView& view, double disparity_sigma_px,
                       double gate_sigmas, DepthFilter* filter);

}  // namespace semap::map_internal
