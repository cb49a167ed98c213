// map.confirm_beyond_m: the far points that no live vertex explained, held for a second sighting. A point
// farther than confirm_beyond_m is noisy (σ_z grows with z²) and SGBM's outliers at range seldom repeat: it
// becomes a vertex only when a point of one of the next map.confirm_window_frames frames lands on it.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/map/internal/depth_votes.h"
#include "engine/map/internal/projection_grid.h"
#include "engine/map/internal/triangulation.h"
#include "engine/map/map_options.h"

namespace semap::map_internal {

// The held points, oldest first. Per frame: StartFrame, AddView for each of its cameras, then Match,
// Confirm and Hold for its points, then DropConfirmed. A frame matches the points held by the earlier
// frames only (it does not confirm its own). Keeps references to the views AddView is given until the next
// StartFrame. Not thread-safe.
class HeldPoints {
 public:
  struct Held {
    Eigen::Vector3d position;
    PointAttributes attributes;
    double depth_m;      // camera-frame depth of the sighting
    std::int64_t frame;  // the frame that saw it
  };

  explicit HeldPoints(const MapOptions& options);

  // Frame `frame` starts: the points held longer than the window are dropped; those left are the ones its
  // points can confirm.
  void StartFrame(std::int64_t frame);
  // The view of the frame's next camera: its points are matched against the held points' projections in it.
  void AddView(const VotingView& view);
  // The held point (an index below the frame's start) that a point of camera `camera` at grid cell (gu, gv),
  // camera-frame depth `depth_m`, lands on (within map.merge_radius_px and map.merge_depth_fraction), or
  // kNoId.
  std::uint32_t Match(std::size_t camera, int gu, int gv, double depth_m) const;
  const Held& operator[](std::uint32_t k) const { return held_[k]; }
  // The point id held point k became this frame, or kNoId.
  std::uint32_t ConfirmedAs(std::uint32_t k) const { return confirmed_as_[k]; }
  // Held point k was confirmed: it became point `id`.
  void Confirm(std::uint32_t k, std::uint32_t id) { confirmed_as_[k] = id; }
  void Hold(const Held& point) { held_.push_back(point); }
  // The frame ends: the points it confirmed leave.
  void DropConfirmed();
  // Every held point, none held afterwards.
  std::vector<Held> TakeAll();
  bool empty() const { return held_.empty(); }
  std::size_t size() const { return held_.size(); }

 private:
  double merge_radius_px_;
  double merge_depth_fraction_;
  int window_frames_;
  std::vector<Held> held_;
  std::size_t earlier_ = 0;                  // held before the frame started
  std::vector<std::uint32_t> confirmed_as_;  // per earlier point
  std::vector<ProjectionGrid> grids_;        // per camera of the frame: the earlier points
};

}  // namespace semap::map_internal
