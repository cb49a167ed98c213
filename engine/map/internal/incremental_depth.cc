// The incremental map's update with visibility votes from depth maps (map.visibility: depth).
#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "engine/core/check.h"
#include "engine/map/internal/incremental_state.h"

namespace semap::map_internal {
namespace {

// Live vertices by where they project in one view, on a grid of merge_radius_px cells: per cell the nearest
// vertex (smallest depth), the one a pixel of that cell sees.
class ProjectionGrid {
 public:
  ProjectionGrid(const VotingView& view, double merge_radius_px)
      : view_(view),
        // View pixels are vote_stride_px full-resolution pixels wide: grid cells per view pixel.
        cells_per_px_(std::sqrt(view.view->rays_per_pixel) / merge_radius_px),
        width_(std::max(1, int(std::ceil(view.view->depth_m.cols * cells_per_px_)))),
        height_(std::max(1, int(std::ceil(view.view->depth_m.rows * cells_per_px_)))),
        cells_(std::size_t(width_) * height_),
        covered_(cells_.size(), 0) {}

  struct Entry {
    float depth_m = std::numeric_limits<float>::infinity();
    std::uint32_t id = kNoId;
  };

  // The grid cell of a world point and its camera-frame depth, or false outside the view; `view_depth_m`
  // (when given) receives the view's depth at the point's pixel.
  bool Locate(const Eigen::Vector3d& p_world, int* gu, int* gv, double* depth_m,
              float* view_depth_m = nullptr) const {
    const Eigen::Vector3d p = view_.ToCamera(p_world);
    if (!(p.z() > 0.0)) return false;
    const Eigen::Vector2d px = view_.view->intrinsics.Project(p);
    const Eigen::Vector2d uv = px * cells_per_px_;
    if (!(uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() < width_ && uv.y() < height_)) return false;
    *gu = int(uv.x());
    *gv = int(uv.y());
    *depth_m = p.z();
    if (view_depth_m) *view_depth_m = view_.view->At(px.x(), px.y());
    return true;
  }
  // Records that a point of the frame lands in cell (gu, gv).
  void Cover(int gu, int gv) { covered_[std::size_t(gv) * width_ + gu] = 1; }
  // Whether a point of the frame landed in the 3×3 cells around (gu, gv).
  bool CoveredAround(int gu, int gv) const {
    bool covered = false;
    ForAround(gu, gv, [&](std::size_t cell) { covered = covered || covered_[cell]; });
    return covered;
  }
  // Keeps `id` in its cell when it is nearer than what the cell holds.
  void Offer(int gu, int gv, double depth_m, std::uint32_t id) {
    Entry& e = cells_[std::size_t(gv) * width_ + gu];
    if (depth_m < e.depth_m) e = {float(depth_m), id};
  }
  // The vertex of the 3×3 cells around (gu, gv) whose depth is closest to depth_m, within `tolerance_m`.
  std::uint32_t Match(int gu, int gv, double depth_m, double tolerance_m) const {
    std::uint32_t best = kNoId;
    double best_gap = tolerance_m;
    ForAround(gu, gv, [&](std::size_t cell) {
      const Entry& e = cells_[cell];
      const double gap = std::abs(double(e.depth_m) - depth_m);
      if (e.id != kNoId && gap <= best_gap) {
        best_gap = gap;
        best = e.id;
      }
    });
    return best;
  }

 private:
  // Calls f(cell index) for each of the 3×3 cells around (gu, gv) inside the grid, row by row.
  template <typename F>
  void ForAround(int gu, int gv, F f) const {
    for (int v = std::max(0, gv - 1); v <= std::min(height_ - 1, gv + 1); ++v) {
      for (int u = std::max(0, gu - 1); u <= std::min(width_ - 1, gu + 1); ++u)
        f(std::size_t(v) * width_ + u);
    }
  }

  const VotingView& view_;
  double cells_per_px_;
  int width_, height_;
  std::vector<Entry> cells_;
  std::vector<char> covered_;
};

}  // namespace

MapUpdateResult IncrementalState::UpdateFromDepth(const LabelledCloud& frame) {
  if (frame.camera_views.size() != frame.camera_centers_world.size() ||
      std::any_of(frame.camera_views.begin(), frame.camera_views.end(),
                  [](const auto& v) { return v == nullptr || v->empty(); })) {
    throw std::invalid_argument(
        "map update: map.visibility: depth needs the depth map of every camera (point input without depth "
        "maps, such as SfM tracks, needs map.visibility: rays)");
  }
  ++frame_;
  MapUpdateResult result;
  auto lap = std::chrono::steady_clock::now();
  std::vector<LatticeKey> nodes;
  for (std::size_t c = 0; c < frame.camera_centers_world.size(); ++c) {
    lattice_.Use(frame.camera_centers_world[c], frame_, &nodes);
    last_camera_ = frame.camera_centers_world[c];
  }
  integrator_.AddFrame(frame.camera_views);

  std::vector<PendingVertex> pending;
  refined_.clear();
  ClassifyByProjection(frame, &result, &pending);
  created_mark_ = NewMark();  // the cells a refinement's removal or an insertion creates
  RemoveRefined(&result);
  InsertAndVote(&pending, &nodes, /*newest_view_votes=*/true, &result, &lap);
  return result;
}

MapUpdateResult IncrementalState::InsertHeld() {
  MapUpdateResult result;
  if (options_.visibility != Visibility::kDepth || unconfirmed_.empty() || integrator_.views().empty()) {
    return result;
  }
  auto lap = std::chrono::steady_clock::now();
  // Each held point becomes a vertex where its one sighting put it: its depth filter starts from that
  // sighting (σ at its depth, as a confirmed pair's first sighting), and its age counts from now, so that the
  // arrival queue stays in frame order.
  const VotingView& view = integrator_.views().back();
  std::vector<PendingVertex> pending;
  std::vector<LatticeKey> nodes;
  for (const Unconfirmed& u : unconfirmed_) {
    const std::uint32_t id = next_point_id_++;
    PointRecord& record = points_[id];
    record.position = u.position;
    record.last_seen = frame_;
    record.sighting_depth_m = u.depth_m;
    if (Fusing()) record.filter.Start(u.position, view.DepthSigma(u.depth_m, options_.disparity_sigma_px));
    pending.push_back({u.position, id, 0, u.attributes});
  }
  result.points_held_inserted = unconfirmed_.size();
  unconfirmed_.clear();
  refined_.clear();
  refined_link_.clear();
  created_mark_ = NewMark();
  // Their rays voted with their frames' depth maps already: only the cells the insertions create are voted,
  // from the views of the window.
  InsertAndVote(&pending, &nodes, /*newest_view_votes=*/false, &result, &lap);
  return result;
}

void IncrementalState::InsertAndVote(std::vector<PendingVertex>* pending, std::vector<LatticeKey>* nodes,
                                     bool newest_view_votes, MapUpdateResult* result,
                                     std::chrono::steady_clock::time_point* lap) {
  for (const PendingVertex& p : *pending) lattice_.Use(p.position, frame_, nodes);
  for (LatticeKey node : *nodes) pending->push_back({lattice_.Position(node), kNoId, node, {}});
  SpatialSort(pending);

  result->locate_ms = Lap(lap);

  // The conflict regions are found as the points go in (see InsertVerticesInheriting), not in a pass of
  // their own before: the same points go in and the same cells go.
  std::vector<char> conflicts_pinned;
  InsertVerticesInheriting(pending, result, &conflicts_pinned);
  AddToBoundary(refined_link_);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> no_rays;
  result->points_rejected_at_seam = DropPinnedConflicts(conflicts_pinned, pending, &no_rays, result);
  CollectCreatedCells();
  result->insert_ms = Lap(lap);

  touched_.clear();
  newly_seen_.clear();
  touch_mark_ = NewMark();
  const std::uint32_t visit_mark = NewMark();
  result->cells_voted = integrator_.Integrate(
      created_cells_, {created_mark_, touch_mark_, visit_mark, newest_view_votes}, &touched_, &newly_seen_);
  counters_.cells_visited += result->cells_voted;
  result->trace_ms = Lap(lap);
  CarveAndFinalise(result, lap);
}

void IncrementalState::ClassifyByProjection(const LabelledCloud& frame, MapUpdateResult* result,
                                            std::vector<PendingVertex>* pending) {
  // One grid per camera of the frame (a stream frame has one), over the live vertices seen from it.
  const std::size_t first_view = integrator_.views().size() - frame.camera_views.size();
  std::vector<ProjectionGrid> grids;
  grids.reserve(frame.camera_views.size());
  const std::uint32_t refined_mark = NewMark();
  // map.refine_depth_ratio: the vertices a nearer view measures again, with the view and grid cell where it
  // does; removed (RemoveRefined) where that view's own points land around them, to replace them.
  struct Candidate {
    std::uint32_t id;
    std::size_t camera;
    int gu, gv;
  };
  std::vector<Candidate> candidates;
  const bool fuse = Fusing();
  for (std::size_t c = 0; c < frame.camera_views.size(); ++c) {
    grids.emplace_back(integrator_.views()[first_view + c], options_.merge_radius_px);
    ProjectionGrid& grid = grids.back();
    if (dt_.dimension() < 0) continue;
    // A vertex this view measures again from much nearer, within the noise of the sighting that placed it,
    // is a candidate, kept out of the grid: no point of this view merges into it.
    const double focal_baseline_m_px = integrator_.views()[first_view + c].focal_baseline_m_px;
    const bool refine =
        options_.refine_depth_ratio > 0.0 && options_.disparity_sigma_px > 0.0 && focal_baseline_m_px > 0.0;
    const double band_per_depth2 =
        refine ? options_.refine_noise_sigmas * options_.disparity_sigma_px / focal_baseline_m_px : 0.0;
    for (auto v = dt_.finite_vertices_begin(); v != dt_.finite_vertices_end(); ++v) {
      if (v->info().steiner || v->info().stamp == refined_mark) continue;  // refined in an earlier camera
      int gu, gv;
      double depth;
      float seen_m = 0.0f;
      if (!grid.Locate(ToEigen(v->point()), &gu, &gv, &depth, refine ? &seen_m : nullptr)) continue;
      if (refine && seen_m > 0.0f && std::isfinite(seen_m)) {
        const auto record = points_.find(v->info().id);
        const double sighting_m = record == points_.end() ? 0.0 : record->second.sighting_depth_m;
        if (seen_m < options_.refine_depth_ratio * sighting_m &&
            std::abs(depth - seen_m) <= band_per_depth2 * sighting_m * sighting_m &&
            Refinable(v->info().id)) {
          candidates.push_back({v->info().id, c, gu, gv});
          v->info().stamp = refined_mark;
          continue;
        }
      }
      std::uint32_t id = v->info().id;
      if (fuse) {
        id = FilterVertex(v, integrator_.views()[first_view + c], result, pending);
        if (id != v->info().id) v->info().stamp = refined_mark;  // removed by RemoveRefined
        if (id == kNoId) continue;
      }
      grid.Offer(gu, gv, depth, id);
    }
  }
  // map.confirm_beyond_m: a far point that no live vertex explains waits for a later frame's point to land on
  // it; the pair becomes one vertex at their mean weighted by 1/σ_z² (σ_z ∝ z²). Held points are matched in a
  // grid of their own per camera, built from the earlier frames' (a frame does not confirm its own points).
  const bool confirm = options_.confirm_beyond_m > 0.0;
  if (confirm) {
    unconfirmed_.erase(std::remove_if(unconfirmed_.begin(), unconfirmed_.end(),
                                      [&](const Unconfirmed& u) {
                                        return frame_ - u.frame > options_.confirm_window_frames;
                                      }),
                       unconfirmed_.end());
  }
  const std::size_t earlier = unconfirmed_.size();
  std::vector<std::uint32_t> promoted(earlier, kNoId);
  std::vector<ProjectionGrid> unconfirmed_grids;
  if (confirm) {
    for (std::size_t c = 0; c < frame.camera_views.size(); ++c) {
      unconfirmed_grids.emplace_back(integrator_.views()[first_view + c], options_.merge_radius_px);
      for (std::size_t k = 0; k < earlier; ++k) {
        int gu, gv;
        double depth;
        if (unconfirmed_grids.back().Locate(unconfirmed_[k].position, &gu, &gv, &depth)) {
          unconfirmed_grids.back().Offer(gu, gv, depth, std::uint32_t(k));
        }
      }
    }
  }
  result->point_ids.assign(frame.size(), kDroppedPoint);
  for (std::uint32_t i = 0; i < frame.size(); ++i) {
    const Eigen::Vector3d& p = frame.positions_world[i];
    const std::uint32_t camera = frame.camera_index[i];
    const double range = (p - frame.camera_centers_world[camera]).norm();
    if (!(range > 0.0) || (options_.max_ray_length_m > 0.0 && range > options_.max_ray_length_m)) {
      ++result->dropped;
      continue;
    }
    ProjectionGrid& grid = grids[camera];
    int gu = 0, gv = 0;
    double depth = 0.0;
    const bool in_view = grid.Locate(p, &gu, &gv, &depth);
    if (in_view) grid.Cover(gu, gv);
    // Fusing, a point within the gate of the vertex it lands on is one more sighting of it, whatever
    // merge_depth_fraction says (at 10 m on KITTI 3 % is 1.2 σ_z: most sightings would become new vertices,
    // each as noisy as one frame).
    const VotingView& view = integrator_.views()[first_view + camera];
    const double merge_tolerance_m = std::max(
        options_.merge_depth_fraction * depth,
        fuse && in_view ? options_.fuse_gate_sigmas * view.DepthSigma(depth, options_.disparity_sigma_px)
                        : 0.0);
    std::uint32_t target = in_view ? grid.Match(gu, gv, depth, merge_tolerance_m) : kNoId;
    if (target != kNoId) {
      ++result->merged;
      SeenAgain(target);
    } else if (confirm && in_view && depth > options_.confirm_beyond_m) {
      const std::uint32_t u =
          unconfirmed_grids[camera].Match(gu, gv, depth, options_.merge_depth_fraction * depth);
      if (u == kNoId) {  // held; its first sighting's attributes go to the vertex (the first-camera rule)
        unconfirmed_.push_back({p, AttributesOf(frame, i), depth, frame_});
        ++result->points_held;
        continue;
      }
      if (promoted[u] != kNoId) {
        target = promoted[u];
        ++result->merged;
        SeenAgain(target);
      } else {
        const Unconfirmed& first = unconfirmed_[u];
        const double w_first = 1.0 / std::pow(first.depth_m, 4), w_now = 1.0 / std::pow(depth, 4);
        target = NewPoint(frame, i, pending);
        PointRecord& record = points_.at(target);
        record.position = (w_first * first.position + w_now * p) / (w_first + w_now);
        record.sighting_depth_m = depth;
        record.support = 2;
        if (fuse) {
          record.filter.Start(first.position, view.DepthSigma(first.depth_m, options_.disparity_sigma_px));
          record.filter.AddInlier(p, view.DepthSigma(depth, options_.disparity_sigma_px));
        }
        pending->back().position = record.position;
        pending->back().attributes = first.attributes;
        promoted[u] = target;
        ++result->points_confirmed;
        grid.Offer(gu, gv, depth, target);
      }
    } else {
      target = NewPoint(frame, i, pending);
      PointRecord& record = points_.at(target);
      record.sighting_depth_m = in_view ? depth : range;
      if (in_view) {
        grid.Offer(gu, gv, depth, target);
        if (fuse) record.filter.Start(p, AlongRaySigma(view, view.ToCamera(p), options_.disparity_sigma_px));
      }
    }
    result->point_ids[i] = target;
  }
  if (confirm) {
    std::vector<Unconfirmed> kept;
    for (std::size_t k = 0; k < unconfirmed_.size(); ++k) {
      if (k >= earlier || promoted[k] == kNoId) kept.push_back(unconfirmed_[k]);
    }
    unconfirmed_.swap(kept);
  }
  for (const Candidate& candidate : candidates) {
    if (grids[candidate.camera].CoveredAround(candidate.gu, candidate.gv)) refined_.push_back(candidate.id);
  }
}

std::uint32_t IncrementalState::FilterVertex(VertexHandle v, const VotingView& view, MapUpdateResult* result,
                                             std::vector<PendingVertex>* pending) {
  const std::uint32_t id = v->info().id;
  PointRecord& record = points_.at(id);
  if (!record.filter.started()) return id;  // placed out of its view: no sighting to start from
  const Eigen::Vector3d position = ToEigen(v->point());
  const Sighting sighting =
      ObserveVertex(position, view, options_.disparity_sigma_px, options_.fuse_gate_sigmas, &record.filter);
  if (sighting == Sighting::kNone) return id;
  if (sighting == Sighting::kOutlier) {
    if (!record.filter.IsOutlier(std::uint32_t(options_.outlier_sightings)) || !Refinable(id)) return id;
    refined_.push_back(id);
    ++result->vertices_outliers;
    return kNoId;
  }
  // Moved when its estimate left it by more than fuse_move_sigmas of its own σ: replaced by a vertex there
  // with a new id (the mesh's deltas name vertices by id, and a vertex's position never changes under it).
  const Eigen::Vector3d estimate = record.filter.Estimate();
  if ((estimate - position).norm() <= options_.fuse_move_sigmas * record.filter.Sigma() || !Refinable(id)) {
    // Not moved in the triangulation: the output follows the estimate once it has left the output's
    // position by fuse_output_sigmas (a frozen vertex's output is final: its triangles were emitted).
    VertexInfo& info = v->info();
    const Eigen::Vector3d& output = info.output_version == 0 ? position : record.output_position;
    if (!info.frozen && (estimate - output).norm() > options_.fuse_output_sigmas * record.filter.Sigma()) {
      record.output_position = estimate;
      if (++info.output_version == 0) info.output_version = 1;  // 0 means "at its triangulation position"
      ++result->vertices_output_moved;
    }
    return id;
  }
  const std::uint32_t successor_id = next_point_id_++;
  PointRecord successor = record;
  successor.vertex = VertexHandle();
  successor.position = estimate;
  successor.last_seen = frame_;
  points_.emplace(successor_id, std::move(successor));
  pending->push_back({estimate, successor_id, 0, v->info().attributes});
  refined_.push_back(id);
  ++result->vertices_moved;
  return successor_id;
}

bool IncrementalState::Refinable(std::uint32_t id) const {
  const auto it = points_.find(id);
  if (it == points_.end() || it->second.vertex == VertexHandle()) return false;
  const VertexHandle v = it->second.vertex;
  if (v->info().frozen || mesher_.IsIrregular(v)) return false;
  std::vector<CellHandle> star;
  dt_.incident_cells(v, std::back_inserter(star));
  return std::none_of(star.begin(), star.end(), [](CellHandle c) { return IsPinned(c); });
}

void IncrementalState::RemoveRefined(MapUpdateResult* result) {
  refined_link_.clear();
  if (refined_.empty()) return;
  std::vector<VertexHandle> removed;
  const std::uint32_t removing = NewMark();
  for (std::uint32_t id : refined_) {
    const VertexHandle v = points_.at(id).vertex;
    v->info().stamp = removing;
    removed.push_back(v);
  }
  // The link of the removed vertices: the staying vertices whose stars the removal rebuilds.
  const std::uint32_t link_mark = NewMark();
  std::vector<VertexHandle> adjacent;
  for (const VertexHandle v : removed) {
    adjacent.clear();
    dt_.finite_adjacent_vertices(v, std::back_inserter(adjacent));
    for (const VertexHandle w : adjacent) {
      if (w->info().stamp == removing || w->info().stamp == link_mark) continue;
      w->info().stamp = link_mark;
      refined_link_.push_back(w);
    }
  }
  // The cells refilling the holes start empty and uncarved, as an insertion's do, and are voted from every
  // stored view: each removal marks the cells it creates (created_mark_) as CGAL hands them over. A cell a
  // later removal destroys was marked in vain; its slot, when reused, holds a new cell of that removal,
  // marked in its turn (tests/engine/map/triangulation_test.cc). One at a time, not CGAL's remove_cluster
  // with a stamp of the cells around the link before and a pass after: the map's CPU a frame −11 % on KITTI
  // 04 at half resolution (bench/results/frame-rate.md, "the map's removals one at a time"). The seen bits of
  // the holes' boundary facets live on in the outer cells.
  const auto mark_created =
      boost::make_function_output_iterator([this](CellHandle c) { c->info().created = created_mark_; });
  for (const VertexHandle v : removed) dt_.remove_and_give_new_cells(v, mark_created);
  for (std::uint32_t id : refined_) points_.erase(id);
  const std::size_t refined = refined_.size() - result->vertices_moved - result->vertices_outliers;
  result->vertices_refined = refined;
  counters_.vertices_refined += refined;
  counters_.vertices_moved += result->vertices_moved;
  counters_.vertices_outliers += result->vertices_outliers;
  refined_.clear();
}

void IncrementalState::AddToBoundary(const std::vector<VertexHandle>& vertices) {
  const std::uint32_t mark = NewMark();
  for (const VertexHandle v : boundary_) v->info().stamp = mark;
  for (const VertexHandle v : vertices) {
    if (v->info().stamp == mark) continue;
    v->info().stamp = mark;
    boundary_.push_back(v);
  }
}

void IncrementalState::InsertVerticesInheriting(std::vector<PendingVertex>* pending, MapUpdateResult* result,
                                                std::vector<char>* conflicts_pinned) {
  boundary_.clear();
  conflicts_pinned->assign(pending->size(), 0);
  if (dt_.dimension() < 3) {
    InsertVertices(pending, result);  // nothing to inherit yet, and no seam
    return;
  }
  inserted_.clear();
  // The cells this pass creates carry `created_now` (set through the boundary facets below: each new cell has
  // one); any other cell of a hole is an old one, destroyed: counted, its vertices listed in boundary_ (the
  // cell itself is freed by the insertion: no handle to it is kept).
  const std::uint32_t created_now = NewMark();
  const std::uint32_t in_boundary = NewMark();
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
    const CellHandle c = dt_.locate(p, lt, li, lj, hint);
    hint = c;
    if (lt == Delaunay::VERTEX) {
      // Exactly where a vertex already is (exact synthetic data can do that): the point is that vertex.
      MergeCoincident(pv, c->vertex(li), result);
      continue;
    }
    hole.clear();
    boundary.clear();
    dt_.find_conflicts(p, c, std::back_inserter(boundary), std::back_inserter(hole));
    if (std::any_of(hole.begin(), hole.end(), blocks)) {
      (*conflicts_pinned)[k] = 1;
      continue;
    }
    for (const CellHandle h : hole) {
      if (h->info().stamp == created_now) continue;
      ++result->cells_destroyed;
      AddVerticesToBoundary(h, in_boundary, kNoMark);
    }
    parents.clear();
    for (const Delaunay::Facet& f : boundary) {
      const CellHandle inside = f.first;
      const CellHandle outside = inside->neighbor(f.second);
      parents.push_back({outside, outside->index(inside), inside->info().free_q, inside->info().matter_q,
                         FacetSeen(inside, f.second)});
    }
    const VertexHandle v =
        dt_.insert_in_hole(p, hole.begin(), hole.end(), boundary.front().first, boundary.front().second);
    for (const Parent& parent : parents) {
      CellInfo& info = parent.outside->neighbor(parent.facet)->info();
      info.free_q = parent.free_q;
      info.matter_q = parent.matter_q;
      info.stamp = created_now;
      if (parent.facet_seen) MarkFacetSeen(parent.outside, parent.facet);
    }
    RecordInserted(pv, v, result);
    hint = v->cell();
  }
}

void IncrementalState::MergeCoincident(const PendingVertex& pv, VertexHandle existing,
                                       MapUpdateResult* result) {
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
  points_.erase(pv.point_id);
}

void IncrementalState::SeenAgain(std::uint32_t id) {
  // Its age restarts (at the granularity of finalisation, so the queue holds a few entries per point): a
  // region still in view is not finalised under the camera's eyes (exact street test: RMSE 0.44 → 0.14 m).
  PointRecord& record = points_.at(id);
  ++record.support;
  if (frame_ - record.last_seen >= options_.finalise_every_frames && record.vertex != VertexHandle()) {
    record.last_seen = frame_;
    arrival_.push_back({id, frame_});
  }
}

void IncrementalState::CollectCreatedCells() {
  // Every cell around a vertex inserted now is new. The cells a refinement's removal created before the
  // insertions (and that these left) lie around its link's vertices: they carry the mark already.
  created_cells_.clear();
  MarkCreatedCells(inserted_, kNoMark, &created_cells_);
  if (refined_link_.empty()) return;
  const std::uint32_t listed = NewMark();
  for (const CellHandle c : created_cells_) c->info().stamp = listed;
  std::vector<CellHandle> star;
  for (const VertexHandle v : refined_link_) {
    star.clear();
    dt_.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().created != created_mark_ || c->info().stamp == listed) continue;
      c->info().stamp = listed;
      created_cells_.push_back(c);
    }
  }
}

}  // namespace semap::map_internal
