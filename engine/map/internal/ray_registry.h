// Compact bookkeeping of the live cameras and rays of the incremental map (map.visibility: rays).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/map/internal/triangulation.h"

namespace semap::map_internal {

struct CameraRecord {
  Eigen::Vector3d center;
  std::int64_t frame = 0;
  std::uint32_t live_rays = 0;
};

struct RayRecord {
  std::uint32_t point = kNoId;
  std::uint32_t camera = kNoId;
  std::uint32_t epoch = 0;  // bumped at each untrace and release: older cell entries become stale
  std::uint32_t mark = 0;   // scratch set membership
  bool live = false;
  // Scratch of one update, for a ray that crosses the re-triangulated region: where along the ray (from the
  // camera) that region lies, so that its retrace stops past it; `slot` indexes the update's affected rays.
  std::uint32_t slot = 0;
  double span_from_m = 0.0;
  double span_to_m = 0.0;
};

// Rays in a slot vector with a free list (slot ids are reused; the epoch keeps old cell entries stale).
// Each cell keeps a vector of RayRef entries; stale ones are purged when the vector would grow, so a cell
// holds at most about twice its live entries. Not thread-safe.
class RayRegistry {
 public:
  std::uint32_t Add(std::uint32_t point, std::uint32_t camera);
  void Release(std::uint32_t ray);
  RayRecord& operator[](std::uint32_t ray) { return rays_[ray]; }
  const RayRecord& operator[](std::uint32_t ray) const { return rays_[ray]; }
  bool IsLive(const RayRef& ref) const {
    return ref.ray < rays_.size() && rays_[ref.ray].live && rays_[ref.ray].epoch == ref.epoch;
  }
  // Appends a live entry of `ray` to `cell`, purging stale entries first when the vector is full.
  void AddRef(CellHandle cell, std::uint32_t ray) const;
  std::size_t num_live() const { return num_live_; }
  std::size_t capacity() const { return rays_.size(); }

 private:
  std::vector<RayRecord> rays_;
  std::vector<std::uint32_t> free_;
  std::size_t num_live_ = 0;
};

}  // namespace semap::map_internal
