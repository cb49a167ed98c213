// Options of the Delaunay map (visibility votes, manifold extraction, incremental update, memory bound).
#pragma once

#include <cstdint>

namespace semap {

// Vote weights (the paper's formula with its typos fixed, see engine/map/internal/vote_weights.h):
//   w_free(d)   = 1 - exp(-d^2 / (2 sigma_free^2))
//   w_matter(d) = 1 - exp(-d^2 / (2 sigma_matter^2))
// A cell is free space when its summed free weight exceeds its summed matter weight.
// How the manifold surface is extracted from the free cells.
enum class SurfaceExtraction {
  // The paper's: region growing from the cell with the highest free vote, adding free neighbours only
  // while the boundary stays manifold. Its greedy order blocks itself: on stereo streets it leaves about
  // a third of the free cells out, and their boundary is spurious surface in front of the true one.
  kGreedyGrowth,
  // Carve every free cell, restore the manifold locally (ManifoldCarver::Repair: the cheaper of filling or
  // trimming around each non-regular vertex), then grow into what is still free. Default.
  kCarveAndRepair,
};

// Where the visibility votes come from.
enum class Visibility {
  // Each frame's depth map (every valid pixel is a ray): cells in the view are voted by sampling them
  // against it (engine/map/internal/depth_votes.h); cells created by an insertion are voted from the views
  // of the last vote_window_frames frames. No per-ray records: nothing is retraced. Needs a depth view per
  // camera (LabelledCloud::camera_views). Default: about 5× faster than kRays with a 4× smaller mesh
  // (bench/RESULTS.md, "Dense votes from depth maps").
  kDepth,
  // One exact walk per point ray through the triangulation (the paper's votes, the reference): rays are
  // recorded in the cells they cross and retraced when those cells change. Any input (SfM tracks too).
  kRays,
};

struct MapOptions {
  Visibility visibility = Visibility::kDepth;
  // kDepth: views kept to vote the cells an insertion creates (≥ 1).
  int vote_window_frames = 8;
  // kDepth: a new point whose projection lies within merge_radius_px (full-resolution px) of a live vertex's
  // in its own view, at a depth within merge_depth_fraction of that vertex's, is that vertex seen again: it
  // adds to the vertex's support instead of becoming a vertex.
  double merge_radius_px = 3.0;
  double merge_depth_fraction = 0.03;
  // kDepth: σ of the stereo disparity (px). A pixel's depth z is uncertain by σ_z = z²·σ/(f·B): a cell is
  // voted free only before that band, matter within it (0 = the paper's votes, exact points).
  double disparity_sigma_px = 0.5;

  double sigma_free_m = 0.05;    // σ_free of the free-space weight (paper: 0.05 m)
  double sigma_matter_m = 0.01;  // σ_matter of the matter weight (paper: 0.01 m)
  // The ray is extended behind its point by ray_extension_factor · σ_matter (paper: 10).
  double ray_extension_factor = 10.0;
  // Rays longer than this (camera to point) are not traced and their point is not inserted; 0 = no limit.
  double max_ray_length_m = 0.0;
  // kRays: a new point closer than this to an existing point (or an earlier point of the same frame) is
  // merged into it: only its ray is added. 0 = never merge.
  double merge_distance_m = 0.05;

  SurfaceExtraction extraction = SurfaceExtraction::kCarveAndRepair;
  // Region growing retries the cells the manifold test refused, in up to this many passes (≥ 1).
  int grow_passes = 3;
  // kCarveAndRepair: the cost, in vote units (one unit = one ray's full weight), of carving one cell that is
  // not free to make a vertex regular, on top of its matter excess; compared with the free votes given up
  // by uncarving instead (≥ 0). Measured insensitive between 0.5 and 2.
  double repair_fill_cost = 0.5;

  // Bounding Steiner points: a jittered lattice of this spacing around every point and camera keeps the
  // convex hull (and its infinite cells) away from the data, so the carved region never touches the hull.
  double steiner_spacing_m = 20.0;
  // Lattice cubes added around the cube of each point/camera, in every direction (≥ 1).
  int steiner_margin_cubes = 1;
  // Mesh triangles touching a Steiner vertex are artefacts of the bounding box; drop them from the output
  // mesh (the internal surface stays a closed 2-manifold either way).
  bool drop_steiner_triangles = true;
  // kDepth: a surface facet no view saw as a surface (the point a view saw through its centroid never within
  // ray_extension_m + seen_noise_sigmas σ_z of its plane) is left out of the mesh: where free space meets
  // space no view saw (above the field of view, behind a facade, past the far range) is no surface (no lids,
  // no roofs of guesses). The mesh is open there. See engine/map/internal/depth_votes.h. A wider tolerance
  // keeps more of the far, noisy surface and more guesses with it (80 urban frames, PS: σ multiples 0 / 0.5 /
  // 1 / 3 put 1.7 / 3.3 / 4.4 / 6.2 % of the area farther than 2 m from the truth; bench/RESULTS.md).
  bool drop_unseen_surface = true;
  double seen_noise_sigmas = 0.0;
  // kDepth with drop_unseen_surface: a hole of at most this many unseen surface facets, connected across
  // edges and ringed by seen facets, is taken as seen (0 = never). Its facets missed the tolerance above by
  // their vertices' stereo noise, not for want of a view: the views saw a surface all around (a facade mapped
  // from afar, seen closer later). Lids and ceilings are large unseen regions and stay out
  // (engine/map/internal/seen_holes.h). The default fills single facets whose three neighbours were seen: 200
  // urban frames, PS: strict RMSE vs Velodyne 3.89 → 3.45 m for 1 point less area within 0.2 m of the truth;
  // 4 facets: 2.99 m for 4.8 points less (bench/RESULTS.md, session 10).
  int fill_unseen_holes_facets = 1;

  // Memory bound: points older than finalise_age_frames frames, or farther than finalise_distance_m from the
  // latest camera (and older than finalise_min_age_frames) are finalised: the triangles touching them are
  // emitted once, then their rays, cells and vertices are released. 0 = never finalise by that criterion.
  // By distance by default: finalising by age cut regions still in view (a drive that turns into a street it
  // saw from afar lost half its surface there; bench/RESULTS.md), while beyond the depth range behind the
  // camera nothing changes any more. The age is counted from a point's last sight (depth) or insertion (rays).
  int finalise_age_frames = 0;
  double finalise_distance_m = 50.0;
  int finalise_min_age_frames = 5;
  // Finalisation runs every this many frames (≥ 1): each run retraces the rays through the released cells,
  // so batching the releases amortises that cost; the live window grows by up to this many frames.
  int finalise_every_frames = 10;

  // Throws semap::InvalidOption naming the offending field.
  void Check() const;

  double ray_extension_m() const { return ray_extension_factor * sigma_matter_m; }
  std::int64_t repair_fill_cost_q() const;  // repair_fill_cost in fixed-point vote units
};

}  // namespace semap
