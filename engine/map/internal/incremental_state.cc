#include "engine/map/internal/incremental_state.h"

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>

#include "engine/core/check.h"
#include "engine/core/parallel.h"
#include "engine/map/internal/seen_holes.h"

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

PointAttributes AttributesOf(const LabelledCloud& frame, std::uint32_t i) {
  PointAttributes attributes;
  if (!frame.labels.empty()) attributes.label = frame.labels[i];
  if (!frame.colors_rgb.empty()) attributes.color_rgb = frame.colors_rgb[i];
  return attributes;
}

void SpatialSort(std::vector<PendingVertex>* pending) {
  std::vector<Point> points;
  points.reserve(pending->size());
  for (const auto& p : *pending) points.push_back(ToPoint(p.position));
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  using Traits = CGAL::Spatial_sort_traits_adapter_3<Kernel, CGAL::Pointer_property_map<Point>::type>;
  CGAL::spatial_sort(order.begin(), order.end(), Traits(CGAL::make_property_map(points)));
  std::vector<PendingVertex> sorted;
  sorted.reserve(order.size());
  for (std::size_t i : order) sorted.push_back((*pending)[i]);
  *pending = std::move(sorted);
}

double Lap(std::chrono::steady_clock::time_point* since) {
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - *since).count();
  *since = now;
  return ms;
}

IncrementalState::IncrementalState(const MapOptions& options)
    : options_(options),
      geometry_(options),
      carver_(&dt_, options.grow_passes, options.repair_fill_cost_q()),
      integrator_(&dt_, options),
      lattice_(options.steiner_spacing_m, options.steiner_margin_cubes),
      mesher_(&dt_, Emit(), [this](VertexHandle v) { return OutputPosition(v); }) {}

Eigen::Vector3d IncrementalState::OutputPosition(VertexHandle v) const {
  if (v->info().steiner || v->info().output_version == 0) return ToEigen(v->point());
  return points_.at(v->info().id).output_position;
}

MapUpdateResult IncrementalState::Update(const LabelledCloud& frame, const std::vector<Observation>& extra) {
  frame.AssertConsistent();
  if (options_.visibility == Visibility::kDepth) {
    if (!extra.empty()) {
      throw std::invalid_argument("map update: extra observations need map.visibility: rays");
    }
    return UpdateFromDepth(frame);
  }
  SEMAP_ASSERT(frame.empty() || frame.camera_index.size() == frame.size(), "every point needs its camera");
  ++frame_;
  MapUpdateResult result;
  auto lap = std::chrono::steady_clock::now();
  for (const Observation& o : extra) {
    if (!points_.count(o.point)) {
      throw std::invalid_argument("map update: observation of unknown point id " + std::to_string(o.point));
    }
    SEMAP_ASSERT(o.camera < frame.camera_centers_world.size(), "observation camera out of range");
  }

  // Cameras of this frame.
  std::vector<std::uint32_t> camera_ids;
  std::vector<LatticeKey> nodes;
  for (const Eigen::Vector3d& c : frame.camera_centers_world) {
    camera_ids.push_back(next_camera_id_);
    cameras_[next_camera_id_++] = CameraRecord{c, frame_, 0};
    lattice_.Use(c, frame_, &nodes);
    last_camera_ = c;
  }

  std::vector<PendingVertex> pending;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> new_rays;  // (point id, camera id)
  ClassifyPoints(frame, camera_ids, &result, &pending, &new_rays);
  for (const Observation& o : extra) new_rays.emplace_back(o.point, camera_ids[o.camera]);
  for (const PendingVertex& p : pending) lattice_.Use(p.position, frame_, &nodes);
  for (LatticeKey node : nodes) pending.push_back({lattice_.Position(node), kNoId, node, {}});
  SpatialSort(&pending);

  // Destroyed cells and the rays through them, untraced in the old triangulation.
  destroyed_.clear();
  std::vector<char> conflicts_pinned;
  CollectConflicts(pending, &conflicts_pinned);
  result.points_rejected_at_seam = DropPinnedConflicts(conflicts_pinned, &pending, &new_rays, &result);
  result.cells_destroyed = destroyed_.size();
  std::vector<std::uint32_t> affected;
  CollectAffectedRays(&affected);
  result.rays_retraced = affected.size();
  result.locate_ms = Lap(&lap);

  InsertVertices(&pending, &result);
  created_mark_ = NewMark();
  MarkCreatedCells(inserted_, kNoMark);
  touched_.clear();
  std::vector<CellHandle> uncarved;
  UncarveBoundaryStars(&uncarved);
  result.cells_uncarved = uncarved.size();
  result.insert_ms = Lap(&lap);

  // Votes: retrace the affected rays, trace the new ones.
  const std::uint32_t touch_mark = NewMark();
  for (CellHandle c : uncarved) {
    if (c->info().stamp != touch_mark) {
      c->info().stamp = touch_mark;
      touched_.push_back(c);
    }
  }
  touch_mark_ = touch_mark;
  TraceRays(affected, +1, /*only_created=*/true);
  std::vector<std::uint32_t> created;
  for (const auto& [point, camera] : new_rays) {
    const std::uint32_t ray = rays_.Add(point, camera);
    points_.at(point).rays.push_back(ray);
    ++cameras_.at(camera).live_rays;
    created.push_back(ray);
  }
  TraceRays(created, +1);
  result.rays_traced = created.size();
  result.trace_ms = Lap(&lap);
  CarveAndFinalise(&result, &lap);
  return result;
}

void IncrementalState::CarveAndFinalise(MapUpdateResult* result, std::chrono::steady_clock::time_point* lap) {
  result->cells_uncarved += ShrinkNonFree();
  result->cells_carved = Regrow();
  MarkSeenSurface();
  FillSeenHoles();
  result->carve_ms = Lap(lap);
  Finalise(result);
  TakeIrregular();
  result->finalise_ms = Lap(lap);
}

void IncrementalState::MarkSeenSurface() {
  if (!Emit().drop_unseen) return;
  std::vector<CellHandle> cells = touched_;
  cells.insert(cells.end(), carve_changed_.begin(), carve_changed_.end());
  integrator_.MarkSeenSurface(cells, NewMark(), &newly_seen_);
}

void IncrementalState::FillSeenHoles() {
  if (!Emit().drop_unseen || options_.fill_unseen_holes_facets == 0) return;
  std::vector<CellHandle> around = touched_;
  around.insert(around.end(), newly_seen_.begin(), newly_seen_.end());
  counters_.facets_taken_as_seen += FillUnseenHoles(&dt_, around, options_.fill_unseen_holes_facets);
}

void IncrementalState::ClassifyPoints(const LabelledCloud& frame,
                                      const std::vector<std::uint32_t>& camera_ids, MapUpdateResult* result,
                                      std::vector<PendingVertex>* pending,
                                      std::vector<std::pair<std::uint32_t, std::uint32_t>>* new_rays) {
  const double merge = options_.merge_distance_m;
  const double voxel = std::max(merge, 1e-3);
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;  // frame-local new points by voxel
  result->point_ids.assign(frame.size(), kDroppedPoint);
  CellHandle hint;
  for (std::uint32_t i = 0; i < frame.size(); ++i) {
    const Eigen::Vector3d& p = frame.positions_world[i];
    const std::uint32_t camera = camera_ids[frame.camera_index[i]];
    const double range = (p - cameras_.at(camera).center).norm();
    if (!(range > 0.0) || (options_.max_ray_length_m > 0.0 && range > options_.max_ray_length_m)) {
      ++result->dropped;
      continue;
    }
    std::uint32_t target = kNoId;
    if (dt_.dimension() == 3) {
      const VertexHandle v = dt_.nearest_vertex(ToPoint(p), hint);
      hint = v->cell();
      if (!dt_.is_infinite(v) && !v->info().steiner && (ToEigen(v->point()) - p).norm() <= merge) {
        target = v->info().id;
      }
    }
    if (target == kNoId) {
      const Eigen::Array3d base = (p / voxel).array().floor();
      for (int dx = -1; dx <= 1 && target == kNoId; ++dx)
        for (int dy = -1; dy <= 1 && target == kNoId; ++dy)
          for (int dz = -1; dz <= 1 && target == kNoId; ++dz) {
            auto it = grid.find(VoxelKey((base + Eigen::Array3d(dx, dy, dz) + 0.5).matrix() * voxel, voxel));
            if (it == grid.end()) continue;
            for (std::uint32_t id : it->second) {
              if ((points_.at(id).position - p).norm() <= merge) {
                target = id;
                break;
              }
            }
          }
    }
    if (target != kNoId) {
      ++result->merged;
    } else {
      target = NewPoint(frame, i, pending);
      grid[VoxelKey(p, voxel)].push_back(target);
    }
    result->point_ids[i] = target;
    new_rays->emplace_back(target, camera);
  }
}

std::uint32_t IncrementalState::NewPoint(const LabelledCloud& frame, std::uint32_t i,
                                         std::vector<PendingVertex>* pending) {
  const std::uint32_t id = next_point_id_++;
  PointRecord& record = points_[id];
  record.position = frame.positions_world[i];
  record.last_seen = frame_;
  pending->push_back({record.position, id, 0, AttributesOf(frame, i)});
  return id;
}

void IncrementalState::CollectConflicts(const std::vector<PendingVertex>& pending,
                                        std::vector<char>* conflicts_pinned) {
  boundary_.clear();
  conflicts_pinned->assign(pending.size(), 0);
  if (dt_.dimension() < 3) return;
  const std::uint32_t mark = NewMark();
  CellHandle hint;
  for (std::size_t k = 0; k < pending.size(); ++k) {
    const PendingVertex& pv = pending[k];
    const Point p = ToPoint(pv.position);
    Delaunay::Locate_type lt;
    int li, lj;
    const CellHandle c = dt_.locate(p, lt, li, lj, hint);
    hint = c;
    if (lt == Delaunay::VERTEX && options_.visibility == Visibility::kDepth) continue;  // merged on insertion
    SEMAP_ASSERT(lt != Delaunay::VERTEX,
                 "a new vertex coincides with an existing one at " << pv.position.transpose());
    conflict_scratch_.clear();
    dt_.find_conflicts(p, c, CGAL::Emptyset_iterator(), std::back_inserter(conflict_scratch_));
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
      destroyed_.push_back(cc);
    }
  }
  CollectBoundary(kNoMark);
}

void IncrementalState::TakeIrregular() { mesher_.AddIrregular(carver_.TakeUnrepaired()); }

std::size_t IncrementalState::DropPinnedConflicts(
    const std::vector<char>& conflicts_pinned, std::vector<PendingVertex>* pending,
    std::vector<std::pair<std::uint32_t, std::uint32_t>>* new_rays, MapUpdateResult* result) {
  std::unordered_set<std::uint32_t> dropped_ids;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < pending->size(); ++k) {
    PendingVertex& pv = (*pending)[k];
    if (!conflicts_pinned[k]) {
      (*pending)[kept++] = std::move(pv);
    } else if (pv.point_id != kNoId) {
      dropped_ids.insert(pv.point_id);
      points_.erase(pv.point_id);
    }
    // A dropped Steiner node stays "required" in the lattice but absent: Finalise skips it.
  }
  pending->resize(kept);
  if (dropped_ids.empty()) return 0;
  new_rays->erase(std::remove_if(new_rays->begin(), new_rays->end(),
                                 [&](const auto& ray) { return dropped_ids.count(ray.first) > 0; }),
                  new_rays->end());
  std::size_t dropped = 0;  // frame points: the new points and those merged into them
  for (std::uint32_t& id : result->point_ids) {
    if (id == kDroppedPoint || !dropped_ids.count(id)) continue;
    id = kDroppedPoint;
    ++dropped;
  }
  result->merged -= dropped - dropped_ids.size();
  result->dropped += dropped;
  return dropped;
}

void IncrementalState::CollectBoundary(std::uint32_t excluded_vertex_mark) {
  boundary_.clear();
  const std::uint32_t mark = NewMark();
  for (const CellHandle c : destroyed_) AddVerticesToBoundary(c, mark, excluded_vertex_mark);
}

void IncrementalState::AddVerticesToBoundary(CellHandle c, std::uint32_t mark,
                                             std::uint32_t excluded_vertex_mark) {
  for (int k = 0; k < 4; ++k) {
    const VertexHandle v = c->vertex(k);
    if (dt_.is_infinite(v) || v->info().stamp == mark || v->info().stamp == excluded_vertex_mark) continue;
    v->info().stamp = mark;
    boundary_.push_back(v);
  }
}

std::uint32_t IncrementalState::StampCellsAround(const std::vector<VertexHandle>& vertices) {
  const std::uint32_t mark = NewMark();
  std::vector<CellHandle> around;
  for (const VertexHandle v : vertices) {
    around.clear();
    dt_.incident_cells(v, std::back_inserter(around));
    for (const CellHandle c : around) c->info().stamp = mark;
  }
  return mark;
}

void IncrementalState::MarkCreatedCells(const std::vector<VertexHandle>& vertices, std::uint32_t old_mark,
                                        std::vector<CellHandle>* newly_marked) {
  std::vector<CellHandle> star;
  for (const VertexHandle v : vertices) {
    star.clear();
    dt_.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == old_mark || c->info().created == created_mark_) continue;
      c->info().created = created_mark_;
      if (newly_marked != nullptr) newly_marked->push_back(c);
    }
  }
}

std::uint32_t IncrementalState::CollectAffectedRays(std::vector<std::uint32_t>* affected) {
  const std::uint32_t mark = NewMark();
  // The new cells fill the destroyed ones exactly, so along each ray they lie within the projections of the
  // destroyed cells it crossed (each of those holds an entry of the ray): that span bounds its retrace.
  struct Line {
    Eigen::Vector3d camera, direction;
  };
  std::vector<Line> lines;
  std::vector<std::uint32_t> line_of;  // per affected ray
  const std::size_t first = affected->size();
  for (const CellHandle c : destroyed_) {
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
        lines.push_back({camera, (points_.at(r.point).position - camera).normalized()});
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

void IncrementalState::RecordInserted(const PendingVertex& pv, VertexHandle v, MapUpdateResult* result) {
  if (pv.point_id != kNoId) {
    v->info() = VertexInfo{pv.point_id, false, false, 0, 0, pv.attributes};
    PointRecord& record = points_.at(pv.point_id);
    record.vertex = v;
    arrival_.push_back({pv.point_id, record.last_seen});
    ++result->inserted;
  } else {
    v->info() = VertexInfo{next_steiner_id_++, true, false, 0, 0, {}};
    steiner_[pv.node] = v;
    ++result->steiner_inserted;
  }
  inserted_.push_back(v);
}

void IncrementalState::InsertVertices(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  inserted_.clear();
  VertexHandle previous;
  for (const PendingVertex& pv : *pending) {
    const std::size_t before = dt_.number_of_vertices();
    const VertexHandle v =
        dt_.insert(ToPoint(pv.position), previous == VertexHandle() ? CellHandle() : previous->cell());
    SEMAP_ASSERT(dt_.number_of_vertices() == before + 1,
                 "vertex at an occupied position " << pv.position.transpose());
    RecordInserted(pv, v, result);
    previous = v;
  }
}

bool IncrementalState::ComputeVotes(std::uint32_t ray, bool only_created, RayVotes* votes) const {
  const RayRecord& r = rays_[ray];
  const RaySpan span{r.span_from_m, r.span_to_m};
  return ComputeRayVotes(dt_, points_.at(r.point).vertex, cameras_.at(r.camera).center, geometry_, votes,
                         only_created ? created_mark_ : 0, only_created ? &span : nullptr);
}

void IncrementalState::ApplyVotes(std::uint32_t ray, int sign, const RayVotes& votes) {
  ++counters_.rays_traced;
  counters_.cells_visited += votes.entries.size();
  for (const RayVotes::Entry& e : votes.entries) {
    CellInfo& info = e.cell->info();
    (e.matter ? info.matter_q : info.free_q) += sign * e.weight_q;
    if (sign > 0) {
      rays_.AddRef(e.cell, ray);
      if (info.stamp != touch_mark_) {
        info.stamp = touch_mark_;
        touched_.push_back(e.cell);
      }
    } else {
      decreased_.push_back(e.cell);
    }
  }
}

void IncrementalState::TraceRays(const std::vector<std::uint32_t>& rays, int sign, bool only_created) {
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

std::size_t IncrementalState::ShrinkNonFree() {
  std::vector<VertexHandle> vertices;
  std::size_t uncarved = 0;
  for (const CellHandle c : touched_) {
    if (!c->info().carved || c->info().IsFree() || IsPinned(c)) continue;
    c->info().carved = false;
    ++uncarved;
    for (int k = 0; k < 4; ++k) vertices.push_back(c->vertex(k));
  }
  if (options_.extraction == SurfaceExtraction::kCarveAndRepair) {
    // Repaired in Regrow, once, with the cells it carves: repairing now, beside the uncarved new cells of
    // the re-triangulated region, would uncarve far around them, only to carve it all again.
    repair_later_ = std::move(vertices);
    return uncarved;
  }
  std::vector<CellHandle> more;
  carver_.Repair(vertices, /*allow_fill=*/false, &more);
  for (const CellHandle c : more) {
    if (c->info().stamp != touch_mark_) {
      c->info().stamp = touch_mark_;
      touched_.push_back(c);
    }
  }
  return uncarved + more.size();
}

void IncrementalState::UncarveBoundaryStars(std::vector<CellHandle>* uncarved) {
  // Carve-and-repair keeps the old carved cells and repairs the boundary vertices in Regrow instead: the
  // stars hold several times more cells than the re-triangulated region, and re-carving them was the
  // largest part of an update.
  if (options_.extraction == SurfaceExtraction::kGreedyGrowth) carver_.UncarveStars(boundary_, uncarved);
}

std::size_t IncrementalState::Regrow() {
  carve_changed_.clear();
  if (options_.extraction == SurfaceExtraction::kCarveAndRepair) {
    repair_later_.insert(repair_later_.end(), boundary_.begin(), boundary_.end());
    const std::size_t carved = carver_.CarveAndRepair(touched_, &carve_changed_, repair_later_);
    repair_later_.clear();
    return carved;
  }
  std::vector<CellHandle> seeds;
  CellHandle best;
  for (const CellHandle c : touched_) {
    if (c->info().carved || !c->info().IsFree() || dt_.is_infinite(c)) continue;
    if (best == CellHandle() || c->info().free_q > best->info().free_q) best = c;
    for (int i = 0; i < 4; ++i) {
      if (c->neighbor(i)->info().carved) {
        seeds.push_back(c);
        break;
      }
    }
  }
  if (seeds.empty() && best != CellHandle()) seeds.push_back(best);
  return carver_.Grow(seeds, &carve_changed_);
}

}  // namespace semap::map_internal
