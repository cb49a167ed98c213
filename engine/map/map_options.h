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

struct MapOptions {
  double sigma_free_m = 0.05;    // σ_free of the free-space weight (paper: 0.05 m)
  double sigma_matter_m = 0.01;  // σ_matter of the matter weight (paper: 0.01 m)
  // The ray is extended behind its point by ray_extension_factor · σ_matter (paper: 10).
  double ray_extension_factor = 10.0;
  // Rays longer than this (camera to point) are not traced and their point is not inserted; 0 = no limit.
  double max_ray_length_m = 0.0;
  // A new point closer than this to an existing point (or an earlier point of the same frame) is merged into
  // it: only its ray is added. 0 = never merge.
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

  // Memory bound: points older than finalise_age_frames frames, or farther than finalise_distance_m from the
  // latest camera (and older than finalise_min_age_frames) are finalised: the triangles touching them are
  // emitted once, then their rays, cells and vertices are released. 0 = never finalise by that criterion.
  int finalise_age_frames = 50;
  double finalise_distance_m = 0.0;
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
