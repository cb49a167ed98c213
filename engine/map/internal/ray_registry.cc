#include "engine/map/internal/ray_registry.h"

#include <algorithm>

#include "engine/core/check.h"

namespace semap::map_internal {

std::uint32_t RayRegistry::Add(std::uint32_t point, std::uint32_t camera) {
  std::uint32_t id;
  if (!free_.empty()) {
    id = free_.back();
    free_.pop_back();
  } else {
    id = std::uint32_t(rays_.size());
    SEMAP_ASSERT(id != kNoId, "too many rays");
    rays_.emplace_back();
  }
  RayRecord& r = rays_[id];
  r.point = point;
  r.camera = camera;
  r.live = true;
  ++num_live_;
  return id;
}

void RayRegistry::Release(std::uint32_t ray) {
  RayRecord& r = rays_[ray];
  SEMAP_ASSERT(r.live);
  r.live = false;
  ++r.epoch;
  free_.push_back(ray);
  --num_live_;
}

void RayRegistry::AddRef(CellHandle cell, std::uint32_t ray) const {
  std::vector<RayRef>& refs = cell->info().rays;
  if (refs.size() == refs.capacity() && !refs.empty()) {
    refs.erase(std::remove_if(refs.begin(), refs.end(), [this](const RayRef& r) { return !IsLive(r); }),
               refs.end());
  }
  refs.push_back({ray, rays_[ray].epoch});
}

}  // namespace semap::map_internal
