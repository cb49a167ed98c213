#include "engine/map/map_options.h"

#include <cmath>

#include "engine/core/check.h"
#include "engine/map/map_types.h"

namespace semap {

void MapOptions::Check() const {
  SEMAP_CHECK_OPTION(sigma_free_m > 0.0, "sigma_free_m", sigma_free_m, "must be > 0");
  SEMAP_CHECK_OPTION(sigma_matter_m > 0.0, "sigma_matter_m", sigma_matter_m, "must be > 0");
  SEMAP_CHECK_OPTION(ray_extension_factor >= 0.0, "ray_extension_factor", ray_extension_factor,
                     "must be >= 0");
  SEMAP_CHECK_OPTION(max_ray_length_m >= 0.0, "max_ray_length_m", max_ray_length_m, "must be >= 0");
  SEMAP_CHECK_OPTION(merge_distance_m >= 0.0, "merge_distance_m", merge_distance_m, "must be >= 0");
  SEMAP_CHECK_OPTION(vote_window_frames >= 1, "vote_window_frames", vote_window_frames, "must be >= 1");
  SEMAP_CHECK_OPTION(seen_window_frames >= 1, "seen_window_frames", seen_window_frames, "must be >= 1");
  SEMAP_CHECK_OPTION(std::isfinite(merge_radius_px) && merge_radius_px > 0.0, "merge_radius_px",
                     merge_radius_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(
      std::isfinite(merge_depth_fraction) && merge_depth_fraction >= 0.0 && merge_depth_fraction < 1.0,
      "merge_depth_fraction", merge_depth_fraction, "must be in [0, 1)");
  SEMAP_CHECK_OPTION(std::isfinite(confirm_beyond_m) && confirm_beyond_m >= 0.0, "confirm_beyond_m",
                     confirm_beyond_m, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(confirm_window_frames >= 1, "confirm_window_frames", confirm_window_frames,
                     "must be >= 1");
  SEMAP_CHECK_OPTION(std::isfinite(disparity_sigma_px) && disparity_sigma_px >= 0.0, "disparity_sigma_px",
                     disparity_sigma_px, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(matter_behind_sigmas) && matter_behind_sigmas >= 0.0,
                     "matter_behind_sigmas", matter_behind_sigmas, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(fuse_gate_sigmas) && fuse_gate_sigmas >= 0.0, "fuse_gate_sigmas",
                     fuse_gate_sigmas, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(fuse_move_sigmas) && fuse_move_sigmas >= 0.0, "fuse_move_sigmas",
                     fuse_move_sigmas, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(fuse_output_sigmas) && fuse_output_sigmas >= 0.0, "fuse_output_sigmas",
                     fuse_output_sigmas, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(outlier_sightings >= 0, "outlier_sightings", outlier_sightings, "must be >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(seen_noise_sigmas) && seen_noise_sigmas >= 0.0, "seen_noise_sigmas",
                     seen_noise_sigmas, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(std::isfinite(seen_halfway_min_radius_m) && seen_halfway_min_radius_m >= 0.0,
                     "seen_halfway_min_radius_m", seen_halfway_min_radius_m, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(fill_unseen_holes_facets >= 0, "fill_unseen_holes_facets", fill_unseen_holes_facets,
                     "must be >= 0");
  SEMAP_CHECK_OPTION(grow_passes >= 1, "grow_passes", grow_passes, "must be >= 1");
  SEMAP_CHECK_OPTION(std::isfinite(repair_fill_cost) && repair_fill_cost >= 0.0, "repair_fill_cost",
                     repair_fill_cost, "must be finite and >= 0");
  SEMAP_CHECK_OPTION(steiner_spacing_m > 0.0, "steiner_spacing_m", steiner_spacing_m, "must be > 0");
  SEMAP_CHECK_OPTION(steiner_margin_cubes >= 1, "steiner_margin_cubes", steiner_margin_cubes, "must be >= 1");
  SEMAP_CHECK_OPTION(finalise_age_frames >= 0, "finalise_age_frames", finalise_age_frames, "must be >= 0");
  SEMAP_CHECK_OPTION(finalise_distance_m >= 0.0, "finalise_distance_m", finalise_distance_m, "must be >= 0");
  SEMAP_CHECK_OPTION(finalise_min_age_frames >= 1, "finalise_min_age_frames", finalise_min_age_frames,
                     "must be >= 1");
  SEMAP_CHECK_OPTION(finalise_every_frames >= 1, "finalise_every_frames", finalise_every_frames,
                     "must be >= 1");
  SEMAP_CHECK_OPTION(steiner_spacing_m > 2.0 * ray_extension_m(), "steiner_spacing_m", steiner_spacing_m,
                     "must exceed twice the ray extension (ray_extension_factor * sigma_matter_m)");
}

std::int64_t MapOptions::repair_fill_cost_q() const {
  return std::llround(repair_fill_cost * kVoteFixedScale);
}

}  // namespace semap
