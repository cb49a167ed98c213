#include "engine/map/internal/ray_tracer.h"

#include "engine/core/check.h"
#include "engine/map/internal/vote_weights.h"

namespace semap::map_internal {
namespace {

// A walk longer than this many cells means a broken triangulation: programmer error, not a user error.
constexpr std::size_t kMaxCellsPerWalk = 50'000'000;

// Appends the finite cells crossed by the segment from vertex `from` to point `to`.
template <typename Fn>
void WalkSegment(const Delaunay& dt, VertexHandle from, const Point& to, Fn&& on_cell) {
  Delaunay::Segment_cell_iterator it(&dt, from, to);
  const Delaunay::Segment_cell_iterator end = dt.segment_traverser_cells_end();
  std::size_t steps = 0;
  for (; it != end; ++it) {
    const CellHandle cell = it;
    if (!dt.is_infinite(cell)) on_cell(cell);
    SEMAP_ASSERT(++steps < kMaxCellsPerWalk, "ray walk does not end");
  }
}

}  // namespace

bool ComputeRayVotes(const Delaunay& dt, VertexHandle target, const Eigen::Vector3d& camera,
                     const RayGeometry& geometry, RayVotes* votes, std::uint32_t only_created) {
  votes->entries.clear();
  const Eigen::Vector3d p = ToEigen(target->point());
  const Eigen::Vector3d to_point = p - camera;
  const double length = to_point.norm();
  if (!(length > 0.0)) return false;
  const double free_saturation = SaturationDistance(geometry.sigma_free_m);
  const double matter_saturation = SaturationDistance(geometry.sigma_matter_m);
  auto skip = [only_created](CellHandle cell) {
    return only_created != 0 && cell->info().created != only_created;
  };
  WalkSegment(dt, target, ToPoint(camera), [&](CellHandle cell) {
    if (skip(cell)) return;
    const double d = DistanceToClosestFacet(cell, target, free_saturation);
    votes->entries.push_back({cell, QuantiseWeight(GaussianComplement(d, geometry.sigma_free_m)), false});
  });
  if (geometry.extension_m > 0.0) {
    const Eigen::Vector3d end = p + to_point * (geometry.extension_m / length);
    WalkSegment(dt, target, ToPoint(end), [&](CellHandle cell) {
      if (skip(cell)) return;
      const double d = DistanceToClosestFacet(cell, target, matter_saturation);
      votes->entries.push_back({cell, QuantiseWeight(GaussianComplement(d, geometry.sigma_matter_m)), true});
    });
  }
  return true;
}

}  // namespace semap::map_internal
