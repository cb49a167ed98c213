// Options of the Delaunay map (visibility votes, manifold extraction, incremental update, memory bound).
#pragma once

#include <cstdint>

#include "engine/core/options.h"

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
  // (bench/results/map-accuracy.md, "Dense votes from depth maps").
  kDepth,
  // One exact walk per point ray through the triangulation (the paper's votes, the reference): rays are
  // recorded in the cells they cross and retraced when those cells change. Any input (SfM tracks too).
  kRays,
};

struct MapOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).

  // Votes.
  Visibility visibility = Visibility::kDepth;
  int vote_window_frames = 8;
  double merge_radius_px = 6.0;
  double merge_depth_fraction = 0.03;
  double disparity_sigma_px = 0.5;
  double matter_behind_sigmas = 3.0;
  double fuse_gate_sigmas = 3.0;
  double fuse_move_sigmas = 3.0;
  double fuse_output_sigmas = 1.0;
  int outlier_sightings = 3;
  double confirm_beyond_m = 20.0;
  int confirm_window_frames = 3;
  double sigma_free_m = 0.05;          // paper: 0.05 m
  double sigma_matter_m = 0.01;        // paper: 0.01 m
  double ray_extension_factor = 10.0;  // paper: 10
  double max_ray_length_m = 0.0;
  double merge_distance_m = 0.05;

  // Surface extraction.
  SurfaceExtraction extraction = SurfaceExtraction::kCarveAndRepair;
  int grow_passes = 3;
  double repair_fill_cost = 0.5;
  double steiner_spacing_m = 20.0;
  int steiner_margin_cubes = 1;
  bool drop_steiner_triangles = true;
  bool drop_unseen_surface = true;
  int seen_window_frames = 12;
  double seen_noise_sigmas = 0.0;
  double seen_halfway_min_radius_m = 0.0;
  int fill_unseen_holes_facets = 1;

  // Memory bound (finalisation).
  int finalise_age_frames = 0;
  double finalise_distance_m = 50.0;
  int finalise_min_age_frames = 5;
  int finalise_every_frames = 10;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    DescribeVotes(v);
    DescribeSurface(v);
    DescribeMemory(v);
  }

  void Check() const;

  double ray_extension_m() const { return ray_extension_factor * sigma_matter_m; }
  std::int64_t repair_fill_cost_q() const;  // repair_fill_cost in fixed-point vote units

 private:
  // The votes and the points (Describe()'s first part).
  template <typename Visitor>
  void DescribeVotes(Visitor& v) {
    v.Enum("visibility", &visibility, {{"depth", Visibility::kDepth}, {"rays", Visibility::kRays}},
           "where the visibility votes come from: depth (each frame's depth map, every valid pixel a ray; "
           "cells sampled against it) | rays (one exact walk per point ray, the paper's votes; also for SfM "
           "input)");
    v.Field("vote_window_frames", &vote_window_frames,
            "depth: the views of this many last frames vote the cells an insertion creates", AtLeast(1));
    // The vertex density of the map: every pixel still votes, whatever the radius. About the spacing of a
    // stream's points (depth.max_points_per_frame over the valid pixels), a surface seen again adds
    // sightings to the vertices it has instead of new ones between them: a smaller radius gives more
    // vertices, a larger mesh and a slower map (insertion, votes and carving scale with the vertices) for
    // slightly more completeness; a larger one, thin structures lost (bench/results/frame-rate.md, "the
    // map's vertex density").
    v.Field(
        "merge_radius_px", &merge_radius_px,
        "depth: a new point projecting within this many full-resolution px of a live vertex in its own view "
        "(and within merge_depth_fraction of its depth) is that vertex seen again: it adds to the vertex's "
        "support instead of becoming a vertex",
        Above(0));
    v.Field("merge_depth_fraction", &merge_depth_fraction, "depth: see merge_radius_px", AtLeast(0).Below(1));
    v.Field(
        "disparity_sigma_px", &disparity_sigma_px,
        "depth: σ of the stereo disparity, px; a pixel's depth z is uncertain by z²σ/(f·B): a cell d before "
        "the pixel's point is voted free with weight Φ(d/σ_z) and matter with 1 − Φ(d/σ_z) (0 = exact "
        "points, the paper's votes)",
        AtLeast(0));
    v.Field(
        "matter_behind_sigmas", &matter_behind_sigmas,
        "depth: matter is voted behind a pixel's point out to the ray extension + this many of its depth σ "
        "(disparity_sigma_px > 0)",
        AtLeast(0));
    // Each live vertex is the inverse-variance estimate of its sightings, one per view, read off the view's
    // depth at the vertex's pixel (engine/map/internal/depth_filter.h says what each rule approximates).
    v.Field(
        "fuse_gate_sigmas", &fuse_gate_sigmas,
        "depth: a view's depth at a live vertex's pixel within this many σ (the view's and the vertex's, "
        "combined) of the vertex's depth is a sighting of it, fused into its position by inverse variance; "
        "0 = vertices stay where their first sighting placed them",
        AtLeast(0));
    // Each move re-triangulates the vertex's star and re-votes its cells: a smaller threshold follows the
    // estimate more closely at a higher cost. On KITTI 04 1σ moved 35,000 vertices in 51 frames (the map's
    // thread +110 ms a frame) for a median 0.008 m lower; 3σ moves 7,600 (its locate step +35 ms)
    // (bench/results/map-accuracy.md, "vertices move at 3σ").
    v.Field("fuse_move_sigmas", &fuse_move_sigmas,
            "depth: a vertex moves to its fused estimate once that lies farther than this many of the "
            "estimate's σ from it",
            AtLeast(0));
    // The output needs no re-triangulation: a vertex the triangulation keeps at its old place is written at
    // its estimate, under a new output id (its triangles go out again in the next mesh delta).
    v.Field(
        "fuse_output_sigmas", &fuse_output_sigmas,
        "depth: the output mesh puts a vertex at its fused estimate once that lies farther than this many "
        "of the estimate's σ from where the output had it (fuse_move_sigmas moves it in the triangulation "
        "too)",
        AtLeast(0));
    v.Field("outlier_sightings", &outlier_sightings,
            "depth: a vertex that at least this many views saw through (their depth at its pixel beyond the "
            "gate, or sky), and more than saw it, leaves the map (an SGBM mismatch, or a moving object that "
            "left); 0 = never",
            AtLeast(0));
    // A far sighting is noisy (σ_z = z²σ/(f·B): 0.5 m at 20 m, 1.2 m at 30 m on KITTI), and a vertex keeps
    // the position it was placed at; SGBM's outliers at range seldom repeat. 80 frames, PS, 20 m and 3
    // frames against 0: area within 0.2 m of the truth 73.3 → 77.9 % (urban), 71.1 → 73.8 % (vegetated);
    // strict RMSE vs Velodyne −1.7 % / −6.1 %, KITTI 04 −13 %; truth completeness −0.6 / −0.5 points,
    // Velodyne pixels covered −0.1 point; fewer vertices, a faster map (bench/results/map-accuracy.md, "Far
    // points confirmed by a second sighting").
    v.Field("confirm_beyond_m", &confirm_beyond_m,
            "depth: a point farther than this (camera-frame depth, m) that no live vertex explains becomes a "
            "vertex only when a point of a later frame lands on it (within merge_radius_px and "
            "merge_depth_fraction), at the two sightings' mean weighted by 1/z⁴; 0 = every point at once",
            AtLeast(0));
    v.Field("confirm_window_frames", &confirm_window_frames,
            "depth: frames an unconfirmed far point waits for its second sighting before it is dropped",
            AtLeast(1));
    v.Field("sigma_free_m", &sigma_free_m, "σ_free of the free-space weight 1 - exp(-d²/(2σ²)), metres",
            Above(0));
    v.Field("sigma_matter_m", &sigma_matter_m, "σ_matter of the matter weight 1 - exp(-d²/(2σ²)), metres",
            Above(0));
    v.Field("ray_extension_factor", &ray_extension_factor,
            "rays are extended behind their point by this many σ_matter (matter votes)", AtLeast(0));
    v.Field("max_ray_length_m", &max_ray_length_m,
            "points farther than this from their camera are neither traced nor inserted; 0 = no limit",
            AtLeast(0));
    v.Field("merge_distance_m", &merge_distance_m,
            "rays: a new point this close to an existing one (or to an earlier point of the same frame) is "
            "merged into it (only its ray is added); 0 = exact duplicates only",
            AtLeast(0));
  }

  // Surface extraction.
  template <typename Visitor>
  void DescribeSurface(Visitor& v) {
    v.Enum("extraction", &extraction,
           {{"carve_and_repair", SurfaceExtraction::kCarveAndRepair},
            {"greedy_growth", SurfaceExtraction::kGreedyGrowth}},
           "manifold surface extraction: carve_and_repair (carve every free cell, repair the manifold "
           "locally, grow) | greedy_growth (the paper's region growing from the most free cell)");
    v.Field("grow_passes", &grow_passes, "region-growing passes retrying the cells the manifold test refused",
            AtLeast(1));
    // Measured insensitive between 0.5 and 2.
    v.Field("repair_fill_cost", &repair_fill_cost,
            "carve_and_repair: cost in ray weights of carving a non-free cell to make a vertex regular "
            "(besides its matter excess), against the free votes given up by uncarving instead",
            AtLeast(0));
    // The jittered lattice keeps the convex hull (and its infinite cells) away from the data, so the carved
    // region never touches the hull.
    v.Field("steiner_spacing_m", &steiner_spacing_m,
            "spacing of the bounding Steiner lattice around every point and camera, metres; more than twice "
            "the ray extension (ray_extension_factor × sigma_matter_m)",
            Above(0));
    v.Field("steiner_margin_cubes", &steiner_margin_cubes,
            "lattice cubes added around the cube of each point and camera, in every direction", AtLeast(1));
    // Those triangles are artefacts of the bounding box; the internal surface stays a closed 2-manifold.
    v.Field("drop_steiner_triangles", &drop_steiner_triangles,
            "leave triangles touching a Steiner vertex out of the mesh");
    // Where free space meets space no view saw (above the field of view, behind a facade, past the far range)
    // is no surface: no lids, no roofs of guesses; the mesh is open there. See
    // engine/map/internal/depth_votes.h.
    v.Field("drop_unseen_surface", &drop_unseen_surface,
            "depth: leave out surface triangles no view saw as a surface (no lids over unseen space)");
    // A facet is looked for when it becomes a surface (engine/map/internal/depth_integrator.h,
    // MarkSeenSurface), often a few frames after its cells were made, when the newest views have driven past
    // it: the older views see it. 200 urban frames, PS: 8 / 12 / 16 / 24 frames give strict RMSE vs Velodyne
    // 3.32 / 2.92 / 2.84 / 2.79 m for 81.6 / 80.4 / 79.9 / 78.9 % of the area within 0.2 m
    // (bench/results/map-accuracy.md, "surface facets looked for when they become one").
    v.Field(
        "seen_window_frames", &seen_window_frames,
        "depth: a facet that becomes a surface is looked for as seen in the views of this many last frames "
        "(their depth maps are kept)",
        AtLeast(1));
    // A wider tolerance keeps more of the far, noisy surface and more guesses with it (80 urban frames, PS: σ
    // multiples 0 / 0.5 / 1 / 3 put 1.7 / 3.3 / 4.4 / 6.2 % of the area farther than 2 m from the truth;
    // bench/results/map-accuracy.md, "The map shows only what was seen").
    v.Field(
        "seen_noise_sigmas", &seen_noise_sigmas,
        "depth: a triangle is seen as a surface when the point a view saw through its centroid lies within "
        "the ray extension + this many depth σ of its plane",
        AtLeast(0));
    // Such a hole's facets missed the tolerance by their vertices' stereo noise, not for want of a view: the
    // views saw a surface all around (a facade mapped from afar, seen closer later). Lids and ceilings are
    // large unseen regions and stay out (engine/map/internal/seen_holes.h). The default fills single facets
    // whose three neighbours were seen: 200 urban frames, PS: strict RMSE vs Velodyne 3.89 → 3.45 m for 1
    // point less area within 0.2 m of the truth; 4 facets: 2.99 m for 4.8 points less
    // (bench/results/map-accuracy.md, "Holes in what was seen").
    // A trade between the area that lies near the truth and the truth that is covered: large facets are
    // mostly far ones, seen at their centroid only, some spanning depth gaps. 200 urban frames, PS: 0 / 1 /
    // 0.7 / 0.5 m put 80.4 / 82.0 / 83.6 / 85.9 % of the area within 0.2 m of the truth, for a truth
    // completeness of 95.1 / 94.9 / 94.7 / 94.1 % and a strict RMSE vs exact depth of 3.76 / 3.75 / 3.89
    // / 4.50 m (the holes they leave are seen through); KITTI 04 strict RMSE 3.07 / 2.99 / 2.91 / 2.86 m at a
    // completeness of 94.4 / 93.8 / 93.0 / 91.5 % (bench/results/map-accuracy.md, "Tried and not kept: map
    // accuracy and fusion").
    v.Field(
        "seen_halfway_min_radius_m", &seen_halfway_min_radius_m,
        "depth: a triangle whose corners lie farther than this from its centroid is seen only where the view "
        "also saw its plane halfway from the centroid to each corner (where the view has depth there); 0 = "
        "the centroid alone",
        AtLeast(0));
    v.Field("fill_unseen_holes_facets", &fill_unseen_holes_facets,
            "depth: a hole of at most this many unseen triangles, connected across edges and ringed by seen "
            "ones, counts as seen; 0 = never",
            AtLeast(0));
  }

  // Memory bound (finalisation).
  template <typename Visitor>
  void DescribeMemory(Visitor& v) {
    // Finalising emits the triangles touching a point once, then releases its rays, cells and vertices. By
    // distance by default: finalising by age cut regions still in view (a drive that turns into a street it
    // saw from afar lost half its surface there; bench/results/map-accuracy.md, "finalising by distance"),
    // while beyond the depth range behind the camera nothing changes any more.
    v.Field(
        "finalise_age_frames", &finalise_age_frames,
        "finalise (emit once, then release) points older than this many frames, counted from a point's last "
        "sight (depth) or insertion (rays); 0 = never by age",
        AtLeast(0));
    v.Field("finalise_distance_m", &finalise_distance_m,
            "finalise points farther than this from the latest camera; 0 = never by distance", AtLeast(0));
    v.Field("finalise_min_age_frames", &finalise_min_age_frames, "minimum age before finalising by distance",
            AtLeast(1));
    v.Field(
        "finalise_every_frames", &finalise_every_frames,
        "run finalisation every this many frames: batching the releases amortises the retracing they cause; "
        "the live window grows by up to this many frames",
        AtLeast(1));
  }
};

}  // namespace semap
