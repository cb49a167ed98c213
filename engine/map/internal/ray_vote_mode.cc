#include "engine/map/internal/ray_vote_mode.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "engine/core/check.h"
#include "engine/core/parallel.h"

namespace semap::map_internal {
namespace {

// Voxel key of the frame-local merge grid.
std::int64_t VoxelKey(const Eigen::Vector3d& p, double size) {
  const Eigen::Array3d c = (p / size).array().floor();
  constexpr std::int64_t kOffset = 1 << 20;
  return ((std::int64_t(c.x()) + kOffset) << 42) | ((std::int64_t(c.y()) + kOffset) << 21) |
         (std::int64_t(c.z()) + kOffset);
}

// Margin added on both sides of a retraced ray's span (see CollectAffectedRays): relative to the distances
// (double rounding) and absolute.
constexpr double kSpanMarginFraction = 1e-9;
constexpr double kSpanMarginM = 1e-9;

}  // namespace

RayVoteMode::RayVoteMode(MapState& state, RegionCarver& carver)
    : state_(state), carver_(carver), geometry_(state.options) {}

void RayVoteMode::CheckInput(const LabelledCloud& frame, const std::vector<Observation>& extra) const {
  SEMAP_ASSERT(frame.empty() || frame.camera_index.size() == frame.size(), "every point needs its camera");
  for (const Observation& o : extra) {
    if (!state_.points.count(o.point)) {
      throw std::invalid_argument("map update: observation of unknown point id " + std::to_string(o.point));
    }
    SEMAP_ASSERT(o.camera < frame.camera_centers_world.size(), "observation camera out of range");
  }
}

std::vector<PendingVertex> RayVoteMode::Locate(const LabelledCloud& frame,
                                               const std::vector<Observation>& extra,
                                               MapUpdateResult* result) {
  AddCameras(frame);
  std::vector<PendingVertex> pending;
  new_rays_.clear();
  ClassifyPoints(frame, result, &pending);
  for (const Observation& o : extra) new_rays_.emplace_back(o.point, camera_ids_[o.camera]);
  state_.AddSteinerNodes(&pending);
  FindConflicts(&pending, result);
  return pending;
}

void RayVoteMode::Insert(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  state_.InsertVertices(pending, result);
  state_.MarkCreatedCells(state_.update.inserted, kNoMark);
  state_.BeginTouched();
  std::vector<CellHandle> uncarved;
  carver_.UncarveBoundaryStars(&uncarved);
  result->cells_uncarved = uncarved.size();
  for (const CellHandle c : uncarved) state_.Touch(c);
}

void RayVoteMode::Vote(MapUpdateResult* result) {
  TraceRays(affected_, +1, /*only_created=*/true);
  const std::vector<std::uint32_t> created = AddNewRays();
  TraceRays(created, +1);
  result->rays_traced = created.size();
}

void RayVoteMode::ReleaseVotes(const std::vector<std::uint32_t>& finalised, std::uint32_t destroyed_mark) {
  std::vector<std::uint32_t> affected;
  CollectAffectedRays(&affected);
  // The finalised points' rays are untraced in full (they may cross cells far from the removed stars).
  decreased_.clear();
  std::vector<std::uint32_t> released;
  for (std::uint32_t id : finalised) {
    const auto& rays = state_.points.at(id).rays;
    released.insert(released.end(), rays.begin(), rays.end());
  }
  TraceRays(released, -1);
  for (std::uint32_t ray : released) {
    auto cam = cameras_.find(rays_[ray].camera);
    if (--cam->second.live_rays == 0 && cam->second.frame < state_.frame) cameras_.erase(cam);
    rays_.Release(ray);
  }
  lost_.clear();  // surviving cells that lost votes
  for (const CellHandle c : decreased_) {
    if (c->info().stamp != destroyed_mark) lost_.push_back(c);
  }
  retrace_.clear();
  for (std::uint32_t ray : affected) {
    if (rays_[ray].live) retrace_.push_back(ray);
  }
}

void RayVoteMode::RevoteReleased(MapUpdateResult* result) {
  for (const CellHandle c : lost_) state_.Touch(c);
  TraceRays(retrace_, +1, /*only_created=*/true);
  result->rays_retraced += retrace_.size();
}

MapSnapshot RayVoteMode::ExportSnapshot() const {
  MapSnapshot s;
  std::map<std::uint32_t, std::uint32_t> camera_index;  // camera id → cloud index (ordered by id)
  for (const auto& [id, camera] : cameras_) camera_index[id] = 0;
  for (auto& [id, index] : camera_index) {
    index = std::uint32_t(s.cloud.camera_centers_world.size());
    s.cloud.camera_centers_world.push_back(cameras_.at(id).center);
    s.cloud.camera_frame_ids.push_back(cameras_.at(id).frame);
  }
  for (const auto& [id, point] : state_.points) s.point_ids.push_back(id);
  std::sort(s.point_ids.begin(), s.point_ids.end());
  for (std::uint32_t i = 0; i < s.point_ids.size(); ++i) {
    const PointRecord& p = state_.points.at(s.point_ids[i]);
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

void RayVoteMode::AddCameras(const LabelledCloud& frame) {
  camera_ids_.clear();
  for (const Eigen::Vector3d& c : frame.camera_centers_world) {
    camera_ids_.push_back(next_camera_id_);
    cameras_[next_camera_id_++] = CameraRecord{c, state_.frame, 0};
  }
}

void RayVoteMode::ClassifyPoints(const LabelledCloud& frame, MapUpdateResult* result,
                                 std::vector<PendingVertex>* pending) {
  const double voxel = std::max(state_.options.merge_distance_m, 1e-3);
  const double max_range = state_.options.max_ray_length_m;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;  // frame-local new points by voxel
  result->point_ids.assign(frame.size(), kDroppedPoint);
  CellHandle hint;
  for (std::uint32_t i = 0; i < frame.size(); ++i) {
    const Eigen::Vector3d& p = frame.positions_world[i];
    const std::uint32_t camera = camera_ids_[frame.camera_index[i]];
    const double range = (p - cameras_.at(camera).center).norm();
    if (!(range > 0.0) || (max_range > 0.0 && range > max_range)) {
      ++result->dropped;
      continue;
    }
    std::uint32_t target = MergeTarget(p, grid, &hint);
    if (target != kNoId) {
      ++result->merged;
    } else {
      target = state_.NewPoint(frame, i, pending);
      grid[VoxelKey(p, voxel)].push_back(target);
    }
    result->point_ids[i] = target;
    new_rays_.emplace_back(target, camera);
  }
}

std::uint32_t RayVoteMode::MergeTarget(
    const Eigen::Vector3d& p, const std::unordered_map<std::int64_t, std::vector<std::uint32_t>>& grid,
    CellHandle* hint) const {
  const double merge = state_.options.merge_distance_m;
  const double voxel = std::max(merge, 1e-3);
  const Delaunay& dt = state_.dt;
  if (dt.dimension() == 3) {
    const VertexHandle v = dt.nearest_vertex(ToPoint(p), *hint);
    *hint = v->cell();
    if (!dt.is_infinite(v) && !v->info().steiner && (ToEigen(v->point()) - p).norm() <= merge) {
      return v->info().id;
    }
  }
  const Eigen::Array3d base = (p / voxel).array().floor();
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        auto it = grid.find(VoxelKey((base + Eigen::Array3d(dx, dy, dz) + 0.5).matrix() * voxel, voxel));
        if (it == grid.end()) continue;
        for (std::uint32_t id : it->second) {
          if ((state_.points.at(id).position - p).norm() <= merge) return id;
        }
      }
  return kNoId;
}

void RayVoteMode::FindConflicts(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  state_.update.destroyed.clear();
  std::vector<char> conflicts_pinned;
  CollectConflicts(*pending, &conflicts_pinned);
  std::unordered_set<std::uint32_t> dropped_ids;
  result->points_rejected_at_seam =
      state_.DropPinnedConflicts(conflicts_pinned, pending, result, &dropped_ids);
  if (!dropped_ids.empty()) {
    new_rays_.erase(std::remove_if(new_rays_.begin(), new_rays_.end(),
                                   [&](const auto& ray) { return dropped_ids.count(ray.first) > 0; }),
                    new_rays_.end());
  }
  result->cells_destroyed = state_.update.destroyed.size();
  affected_.clear();
  CollectAffectedRays(&affected_);
  result->rays_retraced = affected_.size();
}

void RayVoteMode::CollectConflicts(const std::vector<PendingVertex>& pending,
                                   std::vector<char>* conflicts_pinned) {
  Delaunay& dt = state_.dt;
  state_.update.boundary.clear();
  conflicts_pinned->assign(pending.size(), 0);
  if (dt.dimension() < 3) return;
  const std::uint32_t mark = state_.NewMark();
  CellHandle hint;
  for (std::size_t k = 0; k < pending.size(); ++k) {
    const PendingVertex& pv = pending[k];
    const Point p = ToPoint(pv.position);
    Delaunay::Locate_type lt;
    int li, lj;
    const CellHandle c = dt.locate(p, lt, li, lj, hint);
    hint = c;
    SEMAP_ASSERT(lt != Delaunay::VERTEX,
                 "a new vertex coincides with an existing one at " << pv.position.transpose());
    conflict_scratch_.clear();
    dt.find_conflicts(p, c, CGAL::Emptyset_iterator(), std::back_inserter(conflict_scratch_));
    // A cell is destroyed by the insertion of the pending set iff one of them conflicts with it in the old
    // triangulation, so leaving out the vertices that conflict with a pinned cell keeps every seam intact.
    // A pinned cell carved across none of its facets may go: the cells replacing it are uncarved as it was
    // (and pinned where they touch a frozen vertex), so no surface changes. Without that, frozen vertices on
    // the convex hull, or big sealed cells, would keep the map from growing (a drive's new ground lies
    // outside the hull).
    const auto blocks = [&](CellHandle cc) { return IsPinned(cc) && cc->info().CarvedAcrossAny(); };
    if (std::any_of(conflict_scratch_.begin(), conflict_scratch_.end(), blocks)) {
      (*conflicts_pinned)[k] = 1;
      continue;
    }
    for (const CellHandle cc : conflict_scratch_) {
      if (cc->info().stamp == mark) continue;
      cc->info().stamp = mark;
      state_.update.destroyed.push_back(cc);
    }
  }
  state_.CollectBoundary(kNoMark);
}

std::uint32_t RayVoteMode::CollectAffectedRays(std::vector<std::uint32_t>* affected) {
  const std::uint32_t mark = state_.NewMark();
  // The new cells fill the destroyed ones exactly, so along each ray they lie within the projections of the
  // destroyed cells it crossed (each of those holds an entry of the ray): that span bounds its retrace.
  struct Line {
    Eigen::Vector3d camera, direction;
  };
  std::vector<Line> lines;
  const std::size_t first = affected->size();
  for (const CellHandle c : state_.update.destroyed) {
    for (const RayRef& ref : c->info().rays) {
      if (!rays_.IsLive(ref)) continue;
      RayRecord& r = rays_[ref.ray];
      if (r.mark != mark) {
        r.mark = mark;
        r.span_from_m = std::numeric_limits<double>::infinity();
        r.span_to_m = -std::numeric_limits<double>::infinity();
        r.slot = std::uint32_t(affected->size() - first);
        affected->push_back(ref.ray);
        const Eigen::Vector3d camera = cameras_.at(r.camera).center;
        lines.push_back({camera, (state_.points.at(r.point).position - camera).normalized()});
      }
      const Line& line = lines[r.slot];
      for (int k = 0; k < 4; ++k) {
        const double s = (ToEigen(c->vertex(k)->point()) - line.camera).dot(line.direction);
        r.span_from_m = std::min(r.span_from_m, s);
        r.span_to_m = std::max(r.span_to_m, s);
      }
    }
  }
  // A margin against rounding (the walk's own test projects the same vertices the same way).
  for (std::size_t i = first; i < affected->size(); ++i) {
    RayRecord& r = rays_[(*affected)[i]];
    const double margin =
        kSpanMarginFraction * (std::abs(r.span_to_m) + std::abs(r.span_from_m)) + kSpanMarginM;
    r.span_from_m -= margin;
    r.span_to_m += margin;
  }
  return mark;
}

std::vector<std::uint32_t> RayVoteMode::AddNewRays() {
  std::vector<std::uint32_t> created;
  for (const auto& [point, camera] : new_rays_) {
    const std::uint32_t ray = rays_.Add(point, camera);
    state_.points.at(point).rays.push_back(ray);
    ++cameras_.at(camera).live_rays;
    created.push_back(ray);
  }
  return created;
}

bool RayVoteMode::ComputeVotes(std::uint32_t ray, bool only_created, RayVotes* votes) const {
  const RayRecord& r = rays_[ray];
  const RaySpan span{r.span_from_m, r.span_to_m};
  return ComputeRayVotes(state_.dt, state_.points.at(r.point).vertex, cameras_.at(r.camera).center, geometry_,
                         votes, only_created ? state_.update.created_mark : 0,
                         only_created ? &span : nullptr);
}

void RayVoteMode::ApplyVotes(std::uint32_t ray, int sign, const RayVotes& votes) {
  ++state_.counters.rays_traced;
  state_.counters.cells_visited += votes.entries.size();
  for (const RayVotes::Entry& e : votes.entries) {
    CellInfo& info = e.cell->info();
    (e.matter ? info.matter_q : info.free_q) += sign * e.weight_q;
    if (sign > 0) {
      rays_.AddRef(e.cell, ray);
      state_.Touch(e.cell);
    } else {
      decreased_.push_back(e.cell);
    }
  }
}

void RayVoteMode::TraceRays(const std::vector<std::uint32_t>& rays, int sign, bool only_created) {
  // Rays per parallel batch: enough work per batch for the threads, bounded memory for the buffered votes.
  constexpr std::size_t kBatchRays = 2048;
  constexpr std::size_t kGrainRays = 16;
  std::vector<RayVotes> votes(std::min(kBatchRays, rays.size()));
  std::vector<std::uint8_t> valid(votes.size());
  for (std::size_t begin = 0; begin < rays.size(); begin += kBatchRays) {
    const std::size_t count = std::min(kBatchRays, rays.size() - begin);
    // Walks only: nothing below writes to the triangulation, the rays or the point and camera records.
    ParallelFor(std::size_t(0), count, kGrainRays, [&](std::size_t first, std::size_t last) {
      for (std::size_t i = first; i != last; ++i) {
        valid[i] = ComputeVotes(rays[begin + i], only_created, &votes[i]) ? 1 : 0;
      }
    });
    for (std::size_t i = 0; i < count; ++i) {
      if (valid[i]) ApplyVotes(rays[begin + i], sign, votes[i]);
      if (sign < 0) ++rays_[rays[begin + i]].epoch;
    }
  }
}

}  // namespace semap::map_internal
