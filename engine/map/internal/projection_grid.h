// Points by where they project in one depth view, on a grid of map.merge_radius_px cells: per cell the
// nearest one (smallest depth), the one a pixel of that cell sees. The depth mode merges a frame's points
// into the live vertices (and the held points) they land on through it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/map/internal/depth_votes.h"
#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

// Keeps a reference to its view, which must outlive it. Not thread-safe.
class ProjectionGrid {
 public:
  ProjectionGrid(const VotingView& view, double merge_radius_px);

  // The grid cell of a world point and its camera-frame depth, or false outside the view.
  bool Locate(const Eigen::Vector3d& p_world, int* gu, int* gv, double* depth_m) const {
    const Eigen::Vector3d p = view_.ToCamera(p_world);
    if (!(p.z() > 0.0)) return false;
    const Eigen::Vector2d px = view_.view->intrinsics.Project(p);
    const Eigen::Vector2d uv = px * cells_per_px_;
    if (!(uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() < width_ && uv.y() < height_)) return false;
    *gu = int(uv.x());
    *gv = int(uv.y());
    *depth_m = p.z();
    return true;
  }
  // Keeps `id` in its cell when it is nearer than what the cell holds.
  void Offer(int gu, int gv, double depth_m, std::uint32_t id) {
    Entry& e = cells_[std::size_t(gv) * width_ + gu];
    if (depth_m < e.depth_m) e = {float(depth_m), id};
  }
  // The id of the 3×3 cells around (gu, gv) whose depth is closest to depth_m, within `tolerance_m`, or
  // kNoId.
  std::uint32_t Match(int gu, int gv, double depth_m, double tolerance_m) const {
    std::uint32_t best = kNoId;
    double best_gap = tolerance_m;
    ForAround(gu, gv, [&](std::size_t cell) {
      const Entry& e = cells_[cell];
      const double gap = std::abs(double(e.depth_m) - depth_m);
      if (e.id != kNoId && gap <= best_gap) {
        best_gap = gap;
        best = e.id;
      }
    });
    return best;
  }

 private:
  struct Entry {
    float depth_m = std::numeric_limits<float>::infinity();
    std::uint32_t id = kNoId;
  };

  // Calls f(cell index) for each of the 3×3 cells around (gu, gv) inside the grid, row by row.
  template <typename F>
  void ForAround(int gu, int gv, F f) const {
    for (int v = std::max(0, gv - 1); v <= std::min(height_ - 1, gv + 1); ++v) {
      for (int u = std::max(0, gu - 1); u <= std::min(width_ - 1, gu + 1); ++u)
        f(std::size_t(v) * width_ + u);
    }
  }

  const VotingView& view_;
  double cells_per_px_;
  int width_, height_;
  std::vector<Entry> cells_;
};

}  // namespace semap::map_internal
