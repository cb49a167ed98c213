#include "engine/map/incremental_map.h"

#include <algorithm>
#include <map>

#include "engine/map/internal/incremental_state.h"

namespace semap {

using namespace map_internal;

class IncrementalMap::Impl : public IncrementalState {
 public:
  using IncrementalState::IncrementalState;
};

IncrementalMap::IncrementalMap(const MapOptions& options) {
  options.Check();
  impl_ = std::make_unique<Impl>(options);
}
IncrementalMap::~IncrementalMap() = default;
IncrementalMap::IncrementalMap(IncrementalMap&&) noexcept = default;
IncrementalMap& IncrementalMap::operator=(IncrementalMap&&) noexcept = default;

MapUpdateResult IncrementalMap::Update(const LabelledCloud& frame_points,
                                       const std::vector<Observation>& extra) {
  return impl_->Update(frame_points, extra);
}
MapUpdateResult IncrementalMap::InsertHeldPoints() { return impl_->InsertHeld(); }
Mesh IncrementalMap::ExtractMesh() const { return impl_->ExtractMesh().mesh; }
IdentifiedMesh IncrementalMap::ExtractIdentifiedMesh() const { return impl_->ExtractMesh(); }
IdentifiedMesh IncrementalMap::TakeFinalisedMesh() { return impl_->TakeFinalisedMesh(); }
std::vector<CellVotes> IncrementalMap::CellVotesSnapshot() const { return impl_->CellVotesSnapshot(); }
MapSnapshot IncrementalMap::ExportSnapshot() const { return impl_->ExportSnapshot(); }
MapStatistics IncrementalMap::Statistics() const { return impl_->Statistics(); }
MapStatistics IncrementalMap::Sizes() const { return impl_->Sizes(); }

namespace map_internal {

MapSnapshot IncrementalState::ExportSnapshot() const {
  MapSnapshot s;
  std::map<std::uint32_t, std::uint32_t> camera_index;  // camera id → cloud index (ordered by id)
  for (const auto& [id, camera] : cameras_) camera_index[id] = 0;
  for (auto& [id, index] : camera_index) {
    index = std::uint32_t(s.cloud.camera_centers_world.size());
    s.cloud.camera_centers_world.push_back(cameras_.at(id).center);
    s.cloud.camera_frame_ids.push_back(cameras_.at(id).frame);
  }
  for (const auto& [id, point] : points_) s.point_ids.push_back(id);
  std::sort(s.point_ids.begin(), s.point_ids.end());
  for (std::uint32_t i = 0; i < s.point_ids.size(); ++i) {
    const PointRecord& p = points_.at(s.point_ids[i]);
    s.cloud.positions_world.push_back(p.position);
    const PointAttributes& a = p.vertex->info().attributes;
    s.cloud.labels.push_back(a.label);
    s.cloud.colors_rgb.push_back(a.color_rgb);
    s.cloud.camera_index.push_back(camera_index.at(rays_[p.rays.front()].camera));
    for (std::size_t r = 1; r < p.rays.size(); ++r)
      s.extra.push_back({i, camera_index.at(rays_[p.rays[r]].camera)});
  }
  return s;
}

MapStatistics IncrementalState::Sizes() const {
  MapStatistics s = counters_;
  s.num_points = points_.size();
  s.num_steiner_vertices = steiner_.size();
  // number_of_finite_cells() walks every cell; all cells less the infinite ones (those around the hull) is
  // the same count, read off in O(hull).
  if (dt_.dimension() == 3) {
    std::vector<CellHandle> infinite;
    dt_.incident_cells(dt_.infinite_vertex(), std::back_inserter(infinite));
    s.num_cells = dt_.number_of_cells() - infinite.size();
  }
  s.num_rays = rays_.num_live();
  return s;
}

MapStatistics IncrementalState::Statistics() const {
  MapStatistics s = Sizes();
  s.num_carved_cells = CountCarvedCells(dt_);
  s.num_free_cells = CountFreeCells(dt_);
  return s;
}

}  // namespace map_internal
}  // namespace semap
