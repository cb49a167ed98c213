// Visibility votes from depth maps (map.visibility: depth): a cell's votes from one camera view, read off the
// view's depth map instead of walking one ray per point.
//
// How each vote relates to the paper's formula (engine/map/internal/vote_weights.h). A ray camera → p adds
// w_free(d) = 1 − exp(−d²/2σ_free²) to each cell it crosses before p and
// w_matter(d) = 1 − exp(−d²/2σ_matter²) to each cell its extension crosses within ray_extension_m behind p,
// d the distance from p to the cell. With a dense depth map every pixel is such a ray, so the free vote a
// cell C gets from one view is
//   Σ over the pixels x whose ray crosses C in front of its point  w_free(d(x, C)),
// and likewise for matter. Here that sum is estimated by sampling C instead of rasterising it:
//   - the rays crossing C are the pixels of its footprint, the convex hull of its projected vertices: A(C)
//     pixels of the view, each standing for rays_per_pixel full-resolution rays (the vote unit is one
//     full-resolution ray, as one point's ray was in the exact map);
//   - K = 5 sample points of C (its centroid and the midpoints between the centroid and each vertex) each
//     stand for A(C) / K of those rays. A sample s on the ray of pixel x, whose point lies at range
//     r_p = |s| · D(x) / z(s) (D the pixel's depth), is before the point by d = r_p − |s|:
//       d > 0                  → A(C)/K · w_free(d)    free
//       −ray_extension_m ≤ d ≤ 0 → A(C)/K · w_matter(−d) matter
//       otherwise (farther behind) nothing, as for a ray's extension.
// Where this is approximate, and how much:
//   - d is measured from the sample, not from the point to the cell's closest facet: far from the point
//     (d beyond a few σ_free, where w_free saturates, most of the volume) both give weight 1; near the point
//     the sample's d is larger than the exact one (the closest facet is nearer than an interior sample), so a
//     cell touching a surface point gets a larger free weight than the paper's. The decision free vs matter
//     compares the two sums of one cell, and both are sampled the same way.
//   - A(C) counts every pixel of the footprint, including those whose ray ends in front of C (they cross
//     nothing) or has no depth: the samples decide which kind of ray the footprint holds, K = 5 at a time.
//     A footprint that crosses the image border is counted whole; samples outside the image give nothing.
//   - A cell within 5 cm of the camera plane is given the whole image as its footprint; the cell that
//     contains the camera gets one full free vote per ray of the view (every ray starts there).
//   - Each pixel's point carries its own stereo uncertainty (map.disparity_sigma_px > 0): along the ray,
//     σ = hypot(σ_z · r/z, σ_free) with σ_z = z²·σ_d/(f·B), the depth noise of one disparity measurement
//     (floored by the paper's σ_free). The paper's weights treat the point as exact, so a ray whose point
//     lies 2σ behind the true surface votes the cells of that surface free, and a noisy far point carves
//     through what nearer views saw well: summed over many sightings the carved region reaches the far
//     tail of the noise and the mesh lies behind the surface, the more so the farther (KITTI 04: +0.41 m).
//     Here a sample d before the point votes free with the probability that the true surface lies beyond
//     it, Φ(d/σ), and matter with the rest, 1 − Φ(d/σ), out to ray_extension_m + matter_behind_sigmas·σ
//     behind the point (OpenMVS votes matter out to a few σ behind the point too). For n sightings of one
//     surface with noise σ, a sample at the true surface gets n/2 of each in expectation, one in front is
//     free and one behind matter: the carved region ends at the surface, unbiased, and a precise sighting
//     (small σ, votes near 0 or 1) outweighs a noisy one (votes near ½) where they disagree. With
//     disparity_sigma_px = 0 the paper's weights (exact points) are used as they stand above.
//   - Pixels the view marks kFreeToFarRange (sky) vote free up to the view's far range, and no matter: a
//     semantic vote the paper does not have (rays that met nothing within range carve what they crossed).
//
// Not in the paper either: which facets a view sees as a surface (SeenFacets). The surface of the carved
// region also runs where free space meets space no view saw (above the field of view, behind a facade, beyond
// the far range): a wall of unknown, not matter. Such a facet is never where a view saw its depth; the map
// emits only facets some view saw there (map.drop_unseen_surface), so the mesh is open where nothing was
// seen.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/depth_view.h"
#include "engine/map/internal/ray_tracer.h"
#include "engine/map/internal/vote_weights.h"

namespace semap::map_internal {

// A view with its world → camera transform precomputed. Immutable; shared by the threads that vote.
struct VotingView {
  explicit VotingView(std::shared_ptr<const DepthView> v);
  Eigen::Vector3d ToCamera(const Eigen::Vector3d& p_world) const {
    return cam_from_world_rotation * p_world + cam_from_world_translation;
  }
  std::shared_ptr<const DepthView> view;
  Eigen::Matrix3d cam_from_world_rotation;
  Eigen::Vector3d cam_from_world_translation;
  // The depth σ of a point this view's stereo saw at camera-frame depth `depth_m` with disparity noise
  // `disparity_sigma_px` (full-resolution px): σ_z = z²·σ_d/(f·B).
  double DepthSigma(double depth_m, double disparity_sigma_px) const {
    return depth_m * depth_m * disparity_sigma_px / focal_baseline_m_px;
  }
  double image_area_px = 0.0;        // width · height of the view's depth map
  double focal_baseline_m_px = 0.0;  // f·B at full resolution: depth z has disparity f·B / z
};

// The four pixels of a depth map around continuous pixel coordinates (pixel centres at integers).
struct PixelQuad {
  bool inside = false;             // all four pixels lie in the map (else the rest is unset)
  std::array<float, 4> depth_m{};  // (u0, v0), (u0 + 1, v0), (u0, v0 + 1), (u0 + 1, v0 + 1)
  double a = 0.0, b = 0.0;         // the coordinates' fractions past (u0, v0)
  static bool Valid(float depth) { return depth > 0.0f && depth != kFreeToFarRange; }
  bool AllValid() const {
    return inside && Valid(depth_m[0]) && Valid(depth_m[1]) && Valid(depth_m[2]) && Valid(depth_m[3]);
  }
  // 1/z interpolated bilinearly (exact over a plane); AllValid() only.
  double InterpolatedDepth() const;
};
PixelQuad QuadAround(const DepthView& v, const Eigen::Vector2d& uv);

// The depth-vote geometry: the paper's ray geometry and the stereo depth noise.
// (MapOptions declares each value's default and meaning.)
struct DepthVoteGeometry {
  explicit DepthVoteGeometry(const MapOptions& options)
      : ray(options),
        disparity_sigma_px(options.disparity_sigma_px),
        matter_behind_sigmas(options.matter_behind_sigmas),
        seen_noise_sigmas(options.seen_noise_sigmas),
        seen_halfway_min_radius_m(options.seen_halfway_min_radius_m),
        free_saturation_m(SaturationDistance(ray.sigma_free_m)) {}
  RayGeometry ray;
  // σ of the disparity (px): a pixel's depth z is uncertain by σ_z = z² · σ / (f·B). 0 = exact points.
  double disparity_sigma_px;
  // Matter is voted behind a pixel's point out to ray.extension_m + this many of its σ.
  double matter_behind_sigmas;
  // A facet is seen as a surface where the point seen through its centroid lies within ray.extension_m +
  // seen_noise_sigmas · σ_z of its plane.
  double seen_noise_sigmas;
  // A facet whose corners lie farther than this from its centroid is also tested halfway to each corner
  // (0 = never).
  double seen_halfway_min_radius_m;
  // Beyond this distance before its point a sample's free weight is 1 in fixed point (SaturationDistance).
  double free_saturation_m;
};

struct VoteIncrement {
  std::int64_t free_q = 0;
  std::int64_t matter_q = 0;
  bool in_view = false;  // some of the cell is in front of the camera and inside the image's bounds
};

// The votes of the (finite) cell with these vertices from one view (see above). Thread-safe (reads only).
VoteIncrement VoteCell(const std::array<Eigen::Vector3d, 4>& vertices_world, const VotingView& view,
                       const DepthVoteGeometry& geometry);

// Starts fetching the lines of the view's depth map that VoteCell will read for the cell with these vertices:
// those around the pixel of its centroid (the row above, its own and the row below, which hold the samples of
// a cell a few pixels wide, as most cells near a surface are). A loop voting many cells calls it a few cells
// ahead. Reads nothing it waits for and writes nothing: no effect on any result. Thread-safe.
inline void PrefetchCellDepths(const std::array<Eigen::Vector3d, 4>& vertices_world, const VotingView& view) {
  const Eigen::Vector3d centroid =
      view.ToCamera(0.25 * (vertices_world[0] + vertices_world[1] + vertices_world[2] + vertices_world[3]));
  if (centroid.z() < 0.0) return;
  const Eigen::Vector2d uv = view.view->intrinsics.Project(centroid);
  const cv::Mat& depth = view.view->depth_m;
  if (!(uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() < depth.cols && uv.y() < depth.rows)) return;
  const int u = int(uv.x()), v = int(uv.y());
  for (int row = std::max(0, v - 1); row <= std::min(depth.rows - 1, v + 1); ++row) {
    __builtin_prefetch(depth.ptr<float>(row) + u);
  }
}

// Of the facets of the cell with these vertices named by `candidates` (bit i: the facet opposite vertex i),
// those the view sees as a surface: the point the view saw along the ray through the facet's centroid (depth
// interpolated, not sky, not empty) lies within the tolerance (DepthVoteGeometry) of the facet's plane, and
// no farther from its centroid than its vertices are (plus the tolerance); and, for a facet wider than
// seen_halfway_min_radius_m, the points the view saw halfway from the centroid to each corner lie within the
// tolerance of its plane too, where the view has depth there. Thread-safe (reads only).
std::uint8_t SeenFacets(const std::array<Eigen::Vector3d, 4>& vertices_world, std::uint8_t candidates,
                        const VotingView& view, const DepthVoteGeometry& geometry);

// The finite cells of `dt` that may be in `view`: every cell VoteCell gives a vote or SeenFacets a seen facet
// from this view is among them. Found by walking across facets from the cell that holds the camera through
// the cells not wholly outside the view's frustum (behind the camera, or beyond a side of the image); the
// cells meeting a convex region are connected across facets, so none is missed, and ~10 % of a street's live
// cells are visited instead of all. Each visited cell (and the neighbours looked at) gets `visit_mark` in its
// stamp. False when the camera lies outside the triangulation (`cells` then empty). Not thread-safe (writes
// stamps).
bool CellsInView(const Delaunay& dt, const VotingView& view, std::uint32_t visit_mark,
                 std::vector<CellHandle>* cells);

}  // namespace semap::map_internal
