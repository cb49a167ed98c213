#include "engine/map/internal/ray_tracer.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "engine/core/check.h"
#include "engine/map/internal/vote_weights.h"

namespace semap::map_internal {
namespace {

// A walk longer than this many cells means a broken triangulation: programmer error, not a user error.
constexpr std::size_t kMaxCellsPerWalk = 50'000'000;

// Calls on_cell for the finite cells crossed by the segment from vertex `from` to point `to`, in order, while
// it returns true.
template <typename Fn>
void WalkSegment(const Delaunay& dt, VertexHandle from, const Point& to, Fn&& on_cell) {
  Delaunay::Segment_cell_iterator it(&dt, from, to);
  const Delaunay::Segment_cell_iterator end = dt.segment_traverser_cells_end();
  std::size_t steps = 0;
  for (; it != end; ++it) {
    const CellHandle cell = it;
    if (!dt.is_infinite(cell) && !on_cell(cell)) return;
    SEMAP_ASSERT(++steps < kMaxCellsPerWalk, "ray walk does not end");
  }
}

// The range of the projections of a finite cell's vertices on the ray camera + s · direction.
std::pair<double, double> ProjectedRange(CellHandle cell, const Eigen::Vector3d& camera,
                                         const Eigen::Vector3d& direction) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 0; k < 4; ++k) {
    const double s = (ToEigen(cell->vertex(k)->point()) - camera).dot(direction);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return {lo, hi};
}

}  // namespace

bool ComputeRayVotes(const Delaunay& dt, VertexHandle target, const Eigen::Vector3d& camera,
                     const RayGeometry& geometry, RayVotes* votes, std::uint32_t only_created,
                     const RaySpan* span) {
  votes->entries.clear();
  const Eigen::Vector3d p = ToEigen(target->point());
  const Eigen::Vector3d to_point = p - camera;
  const double length = to_point.norm();
  if (!(length > 0.0)) return false;
  const Eigen::Vector3d direction = to_point / length;
  const double free_saturation = SaturationDistance(geometry.sigma_free_m);
  const double matter_saturation = SaturationDistance(geometry.sigma_matter_m);
  auto skip = [only_created](CellHandle cell) {
    return only_created != 0 && cell->info().created != only_created;
  };
  // Walking towards the camera (free votes) the projections decrease; behind the point (matter) they
  // increase.
  auto before_span = [&](CellHandle cell) {
    return span != nullptr && only_created != 0 &&
           ProjectedRange(cell, camera, direction).second < span->from_m;
  };
  auto after_span = [&](CellHandle cell) {
    return span != nullptr && only_created != 0 && ProjectedRange(cell, camera, direction).first > span->to_m;
  };
  WalkSegment(dt, target, ToPoint(camera), [&](CellHandle cell) {
    if (skip(cell)) return !before_span(cell);
    const double d = DistanceToClosestFacet(cell, target, free_saturation);
    votes->entries.push_back({cell, QuantiseWeight(GaussianComplement(d, geometry.sigma_free_m)), false});
    return true;
  });
  if (geometry.extension_m > 0.0) {
    const Eigen::Vector3d end = p + direction * geometry.extension_m;
    WalkSegment(dt, target, ToPoint(end), [&](CellHandle cell) {
      if (skip(cell)) return !after_span(cell);
      const double d = DistanceToClosestFacet(cell, target, matter_saturation);
      votes->entries.push_back({cell, QuantiseWeight(GaussianComplement(d, geometry.sigma_matter_m)), true});
      return true;
    });
  }
  return true;
}

}  // namespace semap::map_internal
