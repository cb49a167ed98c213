#include "engine/map/internal/projection_grid.h"

namespace semap::map_internal {

ProjectionGrid::ProjectionGrid(const VotingView& view, double merge_radius_px)
    : view_(view),
      // View pixels are vote_stride_px full-resolution pixels wide: grid cells per view pixel.
      cells_per_px_(std::sqrt(view.view->rays_per_pixel) / merge_radius_px),
      width_(std::max(1, int(std::ceil(view.view->depth_m.cols * cells_per_px_)))),
      height_(std::max(1, int(std::ceil(view.view->depth_m.rows * cells_per_px_)))),
      cells_(std::size_t(width_) * height_) {}

}  // namespace semap::map_internal
