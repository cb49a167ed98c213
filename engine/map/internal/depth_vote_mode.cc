#include "engine/map/internal/depth_vote_mode.h"

#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

#include "engine/map/internal/depth_filter.h"
#include "engine/map/internal/seen_holes.h"

namespace semap::map_internal {

DepthVoteMode::DepthVoteMode(MapState& state)
    : state_(state), integrator_(&state.dt, state.options), held_(state.options) {}

void DepthVoteMode::CheckInput(const LabelledCloud& frame, const std::vector<Observation>& extra) const {
  if (!extra.empty()) {
    throw std::invalid_argument("map update: extra observations need map.visibility: rays");
  }
  if (frame.camera_views.size() != frame.camera_centers_world.size() ||
      std::any_of(frame.camera_views.begin(), frame.camera_views.end(),
                  [](const auto& v) { return v == nullptr || v->empty(); })) {
    throw std::invalid_argument(
        "map update: map.visibility: depth needs the depth map of every camera (point input without depth "
        "maps, such as SfM tracks, needs map.visibility: rays)");
  }
}

std::vector<PendingVertex> DepthVoteMode::Locate(const LabelledCloud& frame, const std::vector<Observation>&,
                                                 MapUpdateResult* result) {
  integrator_.AddFrame(frame.camera_views);
  newest_view_votes_ = true;
  removing_.clear();
  std::vector<PendingVertex> pending = ClassifyByProjection(frame, result);
  RemoveVertices(result);
  state_.AddSteinerNodes(&pending);
  return pending;
}

std::vector<PendingVertex> DepthVoteMode::LocateHeld(MapUpdateResult* result) {
  // Each held point becomes a vertex where its one sighting put it: its depth filter starts from that
  // sighting (σ at its depth, as a confirmed pair's first sighting), and its age counts from now, so that the
  // arrival queue stays in frame order.
  const VotingView& view = integrator_.views().back();
  const std::vector<HeldPoints::Held> held = held_.TakeAll();
  std::vector<PendingVertex> pending;
  for (const HeldPoints::Held& h : held) {
    const std::uint32_t id = state_.next_point_id++;
    PointRecord& record = state_.points[id];
    record.position = h.position;
    record.last_seen = state_.frame;
    if (Fusing()) {
      record.filter.Start(h.position, view.DepthSigma(h.depth_m, state_.options.disparity_sigma_px));
    }
    pending.push_back({h.position, id, 0, h.attributes});
  }
  result->points_held_inserted = held.size();
  // Their rays voted with their frames' depth maps already: only the cells the insertions create are voted,
  // from the views of the window.
  newest_view_votes_ = false;
  removing_.clear();
  removed_link_.clear();
  state_.AddSteinerNodes(&pending);
  return pending;
}

void DepthVoteMode::Insert(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  // The conflict regions are found as the points go in (see InsertInheriting), not in a pass of their own
  // before: the same points go in and the same cells go.
  std::vector<char> conflicts_pinned;
  InsertInheriting(pending, result, &conflicts_pinned);
  state_.AddToBoundary(removed_link_);
  std::unordered_set<std::uint32_t> dropped_ids;
  result->points_rejected_at_seam =
      state_.DropPinnedConflicts(conflicts_pinned, pending, result, &dropped_ids);
  CollectCreatedCells();
}

void DepthVoteMode::Vote(MapUpdateResult* result) {
  state_.BeginTouched();
  newly_seen_.clear();
  const std::uint32_t visit_mark = state_.NewMark();
  result->cells_voted = integrator_.Integrate(
      created_cells_, {state_.update.created_mark, state_.update.touch_mark, visit_mark, newest_view_votes_},
      &state_.update.touched, &newly_seen_);
  state_.counters.cells_visited += result->cells_voted;
}

void DepthVoteMode::MarkSeenSurface() {
  // map.drop_unseen_surface: the unseen surface facets of the cells this update created or changed the
  // carving of, looked for in the window's views; the cells marked go to newly_seen_.
  if (!state_.options.drop_unseen_surface) return;
  std::vector<CellHandle> cells = state_.update.touched;
  cells.insert(cells.end(), state_.update.carve_changed.begin(), state_.update.carve_changed.end());
  integrator_.MarkSeenSurface(cells, state_.NewMark(), &newly_seen_);
  FillSeenHoles();
}

MapSnapshot DepthVoteMode::ExportSnapshot() const {
  throw std::logic_error("map snapshot: a batch map needs each point's rays (map.visibility: rays)");
}

std::vector<PendingVertex> DepthVoteMode::ClassifyByProjection(const LabelledCloud& frame,
                                                               MapUpdateResult* result) {
  std::vector<PendingVertex> pending;
  // One grid per camera of the frame (a stream frame has one), over the live vertices seen from it.
  const std::size_t first_view = integrator_.views().size() - frame.camera_views.size();
  std::vector<ProjectionGrid> grids;
  grids.reserve(frame.camera_views.size());
  const std::uint32_t removing_mark = state_.NewMark();
  for (std::size_t c = 0; c < frame.camera_views.size(); ++c) {
    const VotingView& view = integrator_.views()[first_view + c];
    grids.emplace_back(view, state_.options.merge_radius_px);
    ProjectLiveVertices(view, removing_mark, &grids.back(), result, &pending);
  }
  // A frame's far points are matched against the points the earlier frames hold, in a grid of their own per
  // camera (a frame does not confirm its own points).
  const bool confirm = state_.options.confirm_beyond_m > 0.0;
  if (confirm) {
    held_.StartFrame(state_.frame);
    for (std::size_t c = 0; c < frame.camera_views.size(); ++c)
      held_.AddView(integrator_.views()[first_view + c]);
  }
  result->point_ids.assign(frame.size(), kDroppedPoint);
  for (std::uint32_t i = 0; i < frame.size(); ++i) {
    const std::uint32_t camera = frame.camera_index[i];
    result->point_ids[i] =
        ClassifyPoint(frame, i, integrator_.views()[first_view + camera], &grids[camera], result, &pending);
  }
  if (confirm) held_.DropConfirmed();
  return pending;
}

void DepthVoteMode::ProjectLiveVertices(const VotingView& view, std::uint32_t removing_mark,
                                        ProjectionGrid* grid, MapUpdateResult* result,
                                        std::vector<PendingVertex>* pending) {
  const Delaunay& dt = state_.dt;
  if (dt.dimension() < 0) return;
  const bool fuse = Fusing();
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    if (v->info().steiner || v->info().stamp == removing_mark) continue;  // removed by an earlier camera
    int gu, gv;
    double depth;
    if (!grid->Locate(ToEigen(v->point()), &gu, &gv, &depth)) continue;
    std::uint32_t id = v->info().id;
    if (fuse) {
      id = FilterVertex(v, view, result, pending);
      if (id != v->info().id) v->info().stamp = removing_mark;  // removed by RemoveVertices
      if (id == kNoId) continue;
    }
    grid->Offer(gu, gv, depth, id);
  }
}

std::uint32_t DepthVoteMode::ClassifyPoint(const LabelledCloud& frame, std::uint32_t i,
                                           const VotingView& view, ProjectionGrid* grid,
                                           MapUpdateResult* result, std::vector<PendingVertex>* pending) {
  const MapOptions& options = state_.options;
  const Eigen::Vector3d& p = frame.positions_world[i];
  const std::size_t camera = frame.camera_index[i];
  const double range = (p - frame.camera_centers_world[camera]).norm();
  if (!(range > 0.0) || (options.max_ray_length_m > 0.0 && range > options.max_ray_length_m)) {
    ++result->dropped;
    return kDroppedPoint;
  }
  Landing at;
  at.in_view = grid->Locate(p, &at.gu, &at.gv, &at.depth_m);
  // Fusing, a point within the gate of the vertex it lands on is one more sighting of it, whatever
  // merge_depth_fraction says (at 10 m on KITTI 3 % is 1.2 σ_z: most sightings would become new vertices,
  // each as noisy as one frame).
  const double merge_tolerance_m =
      std::max(options.merge_depth_fraction * at.depth_m,
               Fusing() && at.in_view
                   ? options.fuse_gate_sigmas * view.DepthSigma(at.depth_m, options.disparity_sigma_px)
                   : 0.0);
  const std::uint32_t target = at.in_view ? grid->Match(at.gu, at.gv, at.depth_m, merge_tolerance_m) : kNoId;
  if (target != kNoId) {
    ++result->merged;
    SeenAgain(target);
    return target;
  }
  if (options.confirm_beyond_m > 0.0 && at.in_view && at.depth_m > options.confirm_beyond_m) {
    return ConfirmOrHold(frame, i, view, camera, at, grid, result, pending);
  }
  return NewSightedPoint(frame, i, view, at, grid, pending);
}

std::uint32_t DepthVoteMode::ConfirmOrHold(const LabelledCloud& frame, std::uint32_t i,
                                           const VotingView& view, std::size_t camera, const Landing& at,
                                           ProjectionGrid* grid, MapUpdateResult* result,
                                           std::vector<PendingVertex>* pending) {
  const Eigen::Vector3d& p = frame.positions_world[i];
  const std::uint32_t u = held_.Match(camera, at.gu, at.gv, at.depth_m);
  if (u == kNoId) {  // held; its first sighting's attributes go to the vertex (the first-camera rule)
    held_.Hold({p, AttributesOf(frame, i), at.depth_m, state_.frame});
    ++result->points_held;
    return kDroppedPoint;
  }
  if (held_.ConfirmedAs(u) != kNoId) {
    const std::uint32_t target = held_.ConfirmedAs(u);
    ++result->merged;
    SeenAgain(target);
    return target;
  }
  const HeldPoints::Held& first = held_[u];
  const double sigma_px = state_.options.disparity_sigma_px;
  const double w_first = 1.0 / std::pow(first.depth_m, 4), w_now = 1.0 / std::pow(at.depth_m, 4);
  const std::uint32_t target = state_.NewPoint(frame, i, pending);
  PointRecord& record = state_.points.at(target);
  record.position = (w_first * first.position + w_now * p) / (w_first + w_now);
  record.support = 2;
  if (Fusing()) {
    record.filter.Start(first.position, view.DepthSigma(first.depth_m, sigma_px));
    record.filter.AddInlier(p, view.DepthSigma(at.depth_m, sigma_px));
  }
  pending->back().position = record.position;
  pending->back().attributes = first.attributes;
  held_.Confirm(u, target);
  ++result->points_confirmed;
  grid->Offer(at.gu, at.gv, at.depth_m, target);
  return target;
}

std::uint32_t DepthVoteMode::NewSightedPoint(const LabelledCloud& frame, std::uint32_t i,
                                             const VotingView& view, const Landing& at, ProjectionGrid* grid,
                                             std::vector<PendingVertex>* pending) {
  const Eigen::Vector3d& p = frame.positions_world[i];
  const std::uint32_t target = state_.NewPoint(frame, i, pending);
  if (at.in_view) {
    grid->Offer(at.gu, at.gv, at.depth_m, target);
    if (Fusing()) {
      state_.points.at(target).filter.Start(
          p, AlongRaySigma(view, view.ToCamera(p), state_.options.disparity_sigma_px));
    }
  }
  return target;
}

void DepthVoteMode::SeenAgain(std::uint32_t id) {
  // Its age restarts (at the granularity of finalisation, so the queue holds a few entries per point): a
  // region still in view is not finalised under the camera's eyes (exact street test: RMSE 0.44 → 0.14 m).
  PointRecord& record = state_.points.at(id);
  ++record.support;
  if (state_.frame - record.last_seen >= state_.options.finalise_every_frames &&
      record.vertex != VertexHandle()) {
    record.last_seen = state_.frame;
    state_.arrival.push_back({id, state_.frame});
  }
}

std::uint32_t DepthVoteMode::FilterVertex(VertexHandle v, const VotingView& view, MapUpdateResult* result,
                                          std::vector<PendingVertex>* pending) {
  const MapOptions& options = state_.options;
  const std::uint32_t id = v->info().id;
  PointRecord& record = state_.points.at(id);
  if (!record.filter.started()) return id;  // placed out of its view: no sighting to start from
  const Eigen::Vector3d position = ToEigen(v->point());
  const Sighting sighting =
      ObserveVertex(position, view, options.disparity_sigma_px, options.fuse_gate_sigmas, &record.filter);
  if (sighting == Sighting::kNone) return id;
  if (sighting == Sighting::kOutlier) {
    if (!record.filter.IsOutlier(std::uint32_t(options.outlier_sightings)) || !Removable(id)) return id;
    removing_.push_back(id);
    ++result->vertices_outliers;
    return kNoId;
  }
  // Moved when its estimate left it by more than fuse_move_sigmas of its own σ: replaced by a vertex there
  // with a new id (the mesh's deltas name vertices by id, and a vertex's position never changes under it).
  const Eigen::Vector3d estimate = record.filter.Estimate();
  if ((estimate - position).norm() <= options.fuse_move_sigmas * record.filter.Sigma() || !Removable(id)) {
    // Not moved in the triangulation: the output follows the estimate once it has left the output's
    // position by fuse_output_sigmas (a frozen vertex's output is final: its triangles were emitted).
    VertexInfo& info = v->info();
    const Eigen::Vector3d& output = info.output_version == 0 ? position : record.output_position;
    if (!info.frozen && (estimate - output).norm() > options.fuse_output_sigmas * record.filter.Sigma()) {
      record.output_position = estimate;
      if (++info.output_version == 0) info.output_version = 1;  // 0 means "at its triangulation position"
      ++result->vertices_output_moved;
    }
    return id;
  }
  const std::uint32_t successor_id = state_.next_point_id++;
  PointRecord successor = record;
  successor.vertex = VertexHandle();
  successor.position = estimate;
  successor.last_seen = state_.frame;
  state_.points.emplace(successor_id, std::move(successor));
  pending->push_back({estimate, successor_id, 0, v->info().attributes});
  removing_.push_back(id);
  ++result->vertices_moved;
  return successor_id;
}

bool DepthVoteMode::Removable(std::uint32_t id) const {
  const auto it = state_.points.find(id);
  if (it == state_.points.end() || it->second.vertex == VertexHandle()) return false;
  const VertexHandle v = it->second.vertex;
  if (v->info().frozen || state_.mesher.IsIrregular(v)) return false;
  std::vector<CellHandle> star;
  state_.dt.incident_cells(v, std::back_inserter(star));
  return std::none_of(star.begin(), star.end(), [](CellHandle c) { return IsPinned(c); });
}

void DepthVoteMode::RemoveVertices(MapUpdateResult* result) {
  removed_link_.clear();
  if (removing_.empty()) return;
  Delaunay& dt = state_.dt;
  std::vector<VertexHandle> removed;
  const std::uint32_t removing = state_.NewMark();
  for (std::uint32_t id : removing_) {
    const VertexHandle v = state_.points.at(id).vertex;
    v->info().stamp = removing;
    removed.push_back(v);
  }
  // The link of the removed vertices: the staying vertices whose stars the removal rebuilds.
  const std::uint32_t link_mark = state_.NewMark();
  std::vector<VertexHandle> adjacent;
  for (const VertexHandle v : removed) {
    adjacent.clear();
    dt.finite_adjacent_vertices(v, std::back_inserter(adjacent));
    for (const VertexHandle w : adjacent) {
      if (w->info().stamp == removing || w->info().stamp == link_mark) continue;
      w->info().stamp = link_mark;
      removed_link_.push_back(w);
    }
  }
  // The cells refilling the holes start empty and uncarved, as an insertion's do, and are voted from every
  // stored view: each removal marks the cells it creates (update.created_mark) as CGAL hands them over. A
  // cell a later removal destroys was marked in vain; its slot, when reused, holds a new cell of that
  // removal, marked in its turn (tests/engine/map/triangulation_test.cc). One at a time, not CGAL's
  // remove_cluster with a stamp of the cells around the link before and a pass after: the map's CPU a frame
  // −11 % on KITTI 04 at half resolution (bench/results/frame-rate.md, "the map's removals one at a time").
  // The seen bits of the holes' boundary facets live on in the outer cells.
  const std::uint32_t created_mark = state_.update.created_mark;
  const auto mark_created = boost::make_function_output_iterator(
      [created_mark](CellHandle c) { c->info().created = created_mark; });
  for (const VertexHandle v : removed) dt.remove_and_give_new_cells(v, mark_created);
  for (std::uint32_t id : removing_) state_.points.erase(id);
  state_.counters.vertices_moved += result->vertices_moved;
  state_.counters.vertices_outliers += result->vertices_outliers;
  removing_.clear();
}

void DepthVoteMode::InsertInheriting(std::vector<PendingVertex>* pending, MapUpdateResult* result,
                                     std::vector<char>* conflicts_pinned) {
  Delaunay& dt = state_.dt;
  state_.update.boundary.clear();
  conflicts_pinned->assign(pending->size(), 0);
  if (dt.dimension() < 3) {
    state_.InsertVertices(pending, result);  // nothing to inherit yet, and no seam
    return;
  }
  state_.update.inserted.clear();
  // The cells this pass creates carry `created_now` (set through the boundary facets below: each new cell has
  // one); any other cell of a hole is an old one, destroyed: counted, its vertices listed in update.boundary
  // (the cell itself is freed by the insertion: no handle to it is kept).
  const std::uint32_t created_now = state_.NewMark();
  const std::uint32_t in_boundary = state_.NewMark();
  // A pinned cell carved across a facet must stay (its surface is final): a point whose conflict region holds
  // one is left out. Such a cell is never destroyed, so it is in the region of every later point in its
  // sphere: the points left out are those whose region in the old triangulation held one (a cell of the old
  // triangulation goes iff a new point lies in its sphere), as a pass over the old triangulation before the
  // insertions would find. A cell created now is uncarved and unsealed: never one. A pinned cell carved
  // across none of its facets may go: the cells replacing it are uncarved as it was (and pinned where they
  // touch a frozen vertex), so no surface changes. Without that, frozen vertices on the convex hull, or big
  // sealed cells, would keep the map from growing (a drive's new ground lies outside the hull).
  const auto blocks = [](CellHandle cc) { return IsPinned(cc) && cc->info().CarvedAcrossAny(); };
  std::vector<CellHandle> hole;
  std::vector<Delaunay::Facet> boundary;
  struct Parent {
    CellHandle outside;
    int facet;  // of `outside`, facing the hole
    std::int64_t free_q, matter_q;
    bool facet_seen;  // the boundary facet was seen as a surface (CellInfo::seen_facets)
  };
  std::vector<Parent> parents;
  CellHandle hint;
  for (std::size_t k = 0; k < pending->size(); ++k) {
    const PendingVertex& pv = (*pending)[k];
    const Point p = ToPoint(pv.position);
    Delaunay::Locate_type lt;
    int li, lj;
    const CellHandle c = dt.locate(p, lt, li, lj, hint);
    hint = c;
    if (lt == Delaunay::VERTEX) {
      // Exactly where a vertex already is (exact synthetic data can do that): the point is that vertex.
      MergeCoincident(pv, c->vertex(li), result);
      continue;
    }
    hole.clear();
    boundary.clear();
    dt.find_conflicts(p, c, std::back_inserter(boundary), std::back_inserter(hole));
    if (std::any_of(hole.begin(), hole.end(), blocks)) {
      (*conflicts_pinned)[k] = 1;
      continue;
    }
    for (const CellHandle h : hole) {
      if (h->info().stamp == created_now) continue;
      ++result->cells_destroyed;
      state_.AddVerticesToBoundary(h, in_boundary, kNoMark);
    }
    parents.clear();
    for (const Delaunay::Facet& f : boundary) {
      const CellHandle inside = f.first;
      const CellHandle outside = inside->neighbor(f.second);
      parents.push_back({outside, outside->index(inside), inside->info().free_q, inside->info().matter_q,
                         FacetSeen(inside, f.second)});
    }
    const VertexHandle v =
        dt.insert_in_hole(p, hole.begin(), hole.end(), boundary.front().first, boundary.front().second);
    for (const Parent& parent : parents) {
      CellInfo& info = parent.outside->neighbor(parent.facet)->info();
      info.free_q = parent.free_q;
      info.matter_q = parent.matter_q;
      info.stamp = created_now;
      if (parent.facet_seen) MarkFacetSeen(parent.outside, parent.facet);
    }
    state_.RecordInserted(pv, v, result);
    hint = v->cell();
  }
}

void DepthVoteMode::MergeCoincident(const PendingVertex& pv, VertexHandle existing, MapUpdateResult* result) {
  if (pv.point_id == kNoId) return;  // a Steiner node on a point: not needed there
  const bool onto_point = !existing->info().steiner;
  for (std::uint32_t& id : result->point_ids) {
    if (id != pv.point_id) continue;
    if (onto_point) {
      id = existing->info().id;
      ++result->merged;
    } else {
      id = kDroppedPoint;
      ++result->dropped;
    }
  }
  if (onto_point) SeenAgain(existing->info().id);
  state_.points.erase(pv.point_id);
}

void DepthVoteMode::CollectCreatedCells() {
  // Every cell around a vertex inserted now is new. The cells a removal created before the insertions (and
  // that these left) lie around its link's vertices: they carry the mark already.
  created_cells_.clear();
  state_.MarkCreatedCells(state_.update.inserted, kNoMark, &created_cells_);
  if (removed_link_.empty()) return;
  const std::uint32_t listed = state_.NewMark();
  for (const CellHandle c : created_cells_) c->info().stamp = listed;
  std::vector<CellHandle> star;
  for (const VertexHandle v : removed_link_) {
    star.clear();
    state_.dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().created != state_.update.created_mark || c->info().stamp == listed) continue;
      c->info().stamp = listed;
      created_cells_.push_back(c);
    }
  }
}

void DepthVoteMode::FillSeenHoles() {
  if (state_.options.fill_unseen_holes_facets == 0) return;
  std::vector<CellHandle> around = state_.update.touched;
  around.insert(around.end(), newly_seen_.begin(), newly_seen_.end());
  state_.counters.facets_taken_as_seen +=
      FillUnseenHoles(&state_.dt, around, state_.options.fill_unseen_holes_facets);
}

}  // namespace semap::map_internal
