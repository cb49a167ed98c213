#include "engine/map/internal/held_points.h"

#include <algorithm>
#include <utility>

namespace semap::map_internal {

HeldPoints::HeldPoints(const MapOptions& options)
    : merge_radius_px_(options.merge_radius_px),
      merge_depth_fraction_(options.merge_depth_fraction),
      window_frames_(options.confirm_window_frames) {}

void HeldPoints::StartFrame(std::int64_t frame) {
  held_.erase(std::remove_if(held_.begin(), held_.end(),
                             [&](const Held& h) { return frame - h.frame > window_frames_; }),
              held_.end());
  earlier_ = held_.size();
  confirmed_as_.assign(earlier_, kNoId);
  grids_.clear();
}

void HeldPoints::AddView(const VotingView& view) {
  grids_.emplace_back(view, merge_radius_px_);
  for (std::size_t k = 0; k < earlier_; ++k) {
    int gu, gv;
    double depth;
    if (grids_.back().Locate(held_[k].position, &gu, &gv, &depth)) {
      grids_.back().Offer(gu, gv, depth, std::uint32_t(k));
    }
  }
}

std::uint32_t HeldPoints::Match(std::size_t camera, int gu, int gv, double depth_m) const {
  return grids_[camera].Match(gu, gv, depth_m, merge_depth_fraction_ * depth_m);
}

void HeldPoints::DropConfirmed() {
  std::vector<Held> kept;
  for (std::size_t k = 0; k < held_.size(); ++k) {
    if (k >= earlier_ || confirmed_as_[k] == kNoId) kept.push_back(held_[k]);
  }
  held_.swap(kept);
  earlier_ = 0;
  confirmed_as_.clear();
}

std::vector<HeldPoints::Held> HeldPoints::TakeAll() {
  std::vector<Held> all;
  all.swap(held_);
  earlier_ = 0;
  confirmed_as_.clear();
  grids_.clear();
  return all;
}

}  // namespace semap::map_internal
