// The incremental map's update with visibility votes from depth maps (map.visibility: depth).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "engine/core/check.h"
#include "engine/core/parallel.h"
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
      for (int u = std::max(0, gu - 1); u <= std::min(width_ - 1, gu + 1); ++u) f(std::size_t(v) * width_ + u);
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
    views_.emplace_back(frame.camera_views[c]);
  }
  while (views_.size() > std::size_t(options_.vote_window_frames) * std::max<std::size_t>(1, frame.camera_views.size())) {
    views_.pop_front();
  }

  std::vector<PendingVertex> pending;
  refined_.clear();
  ClassifyByProjection(frame, &result, &pending);
  created_mark_ = NewMark();  // the cells a refinement's removal or an insertion creates
  RemoveRefined(&result);
  for (const PendingVertex& p : pending) lattice_.Use(p.position, frame_, &nodes);
  for (LatticeKey node : nodes) pending.push_back({lattice_.Position(node), kNoId, node, {}});
  SpatialSort(&pending);

  destroyed_.clear();
  std::vector<char> conflicts_pinned;
  CollectConflicts(pending, &conflicts_pinned);
  AddToBoundary(refined_link_);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> no_rays;
  result.points_rejected_at_seam = DropPinnedConflicts(conflicts_pinned, &pending, &no_rays, &result);
  result.cells_destroyed = destroyed_.size();
  result.locate_ms = Lap(&lap);

  InsertVerticesInheriting(&pending, &result);
  CollectCreatedCells();
  result.insert_ms = Lap(&lap);

  touched_.clear();
  touch_mark_ = NewMark();
  result.cells_voted = VoteFromViews();
  result.trace_ms = Lap(&lap);
  CarveAndFinalise(&result, &lap);
  return result;
}

void IncrementalState::ClassifyByProjection(const LabelledCloud& frame, MapUpdateResult* result,
                                            std::vector<PendingVertex>* pending) {
  // One grid per camera of the frame (a stream frame has one), over the live vertices seen from it.
  const std::size_t first_view = views_.size() - frame.camera_views.size();
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
  for (std::size_t c = 0; c < frame.camera_views.size(); ++c) {
    grids.emplace_back(views_[first_view + c], options_.merge_radius_px);
    ProjectionGrid& grid = grids.back();
    if (dt_.dimension() < 0) continue;
    // A vertex this view measures again from much nearer, within the noise of the sighting that placed it,
    // is a candidate, kept out of the grid: no point of this view merges into it.
    const double focal_baseline_m_px = views_[first_view + c].focal_baseline_m_px;
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
            std::abs(depth - seen_m) <= band_per_depth2 * sighting_m * sighting_m && Refinable(v->info().id)) {
          candidates.push_back({v->info().id, c, gu, gv});
          v->info().stamp = refined_mark;
          continue;
        }
      }
      grid.Offer(gu, gv, depth, v->info().id);
    }
  }
  // map.confirm_beyond_m: a far point that no live vertex explains waits for a later frame's point to land on
  // it; the pair becomes one vertex at their mean weighted by 1/σ_z² (σ_z ∝ z²). Held points are matched in a
  // grid of their own per camera, built from the earlier frames' (a frame does not confirm its own points).
  const bool confirm = options_.confirm_beyond_m > 0.0;
  if (confirm) {
    unconfirmed_.erase(std::remove_if(unconfirmed_.begin(), unconfirmed_.end(),
                                      [&](const Unconfirmed& u) { return frame_ - u.frame > options_.confirm_window_frames; }),
                       unconfirmed_.end());
  }
  const std::size_t earlier = unconfirmed_.size();
  std::vector<std::uint32_t> promoted(earlier, kNoId);
  std::vector<ProjectionGrid> unconfirmed_grids;
  if (confirm) {
    for (std::size_t c = 0; c < frame.camera_views.size(); ++c) {
      unconfirmed_grids.emplace_back(views_[first_view + c], options_.merge_radius_px);
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
    std::uint32_t target = in_view ? grid.Match(gu, gv, depth, options_.merge_depth_fraction * depth) : kNoId;
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
        pending->back().position = record.position;
        pending->back().attributes = first.attributes;
        promoted[u] = target;
        ++result->points_confirmed;
        grid.Offer(gu, gv, depth, target);
      }
    } else {
      target = NewPoint(frame, i, pending);
      points_.at(target).sighting_depth_m = in_view ? depth : range;
      if (in_view) grid.Offer(gu, gv, depth, target);
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

bool IncrementalState::Refinable(std::uint32_t id) const {
  const auto it = points_.find(id);
  if (it == points_.end() || it->second.vertex == VertexHandle()) return false;
  const VertexHandle v = it->second.vertex;
  if (v->info().frozen || irregular_.count(&*v)) return false;
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
  const std::uint32_t old_mark = StampCellsAround(refined_link_);
  // The cells refilling the holes start empty and uncarved, as an insertion's do, and are voted from every
  // stored view (created_mark_). The seen bits of the holes' boundary facets live on in the outer cells.
  dt_.remove_cluster(removed.begin(), removed.end());
  for (std::uint32_t id : refined_) points_.erase(id);
  MarkCreatedCells(refined_link_, old_mark);
  result->vertices_refined = refined_.size();
  counters_.vertices_refined += refined_.size();
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

void IncrementalState::InsertVerticesInheriting(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  if (dt_.dimension() < 3) {
    InsertVertices(pending, result);  // nothing to inherit yet
    return;
  }
  inserted_.clear();
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
  for (const PendingVertex& pv : *pending) {
    const Point p = ToPoint(pv.position);
    Delaunay::Locate_type lt;
    int li, lj;
    const CellHandle c = dt_.locate(p, lt, li, lj, hint);
    if (lt == Delaunay::VERTEX) {
      // Exactly where a vertex already is (exact synthetic data can do that): the point is that vertex.
      MergeCoincident(pv, c->vertex(li), result);
      continue;
    }
    hole.clear();
    boundary.clear();
    dt_.find_conflicts(p, c, std::back_inserter(boundary), std::back_inserter(hole));
    parents.clear();
    for (const Delaunay::Facet& f : boundary) {
      const CellHandle inside = f.first;
      const CellHandle outside = inside->neighbor(f.second);
      parents.push_back({outside, outside->index(inside), inside->info().free_q, inside->info().matter_q,
                         FacetSeen(inside, f.second)});
    }
    const VertexHandle v = dt_.insert_in_hole(p, hole.begin(), hole.end(), boundary.front().first,
                                              boundary.front().second);
    for (const Parent& parent : parents) {
      CellInfo& info = parent.outside->neighbor(parent.facet)->info();
      info.free_q = parent.free_q;
      info.matter_q = parent.matter_q;
      if (parent.facet_seen) MarkFacetSeen(parent.outside, parent.facet);
    }
    RecordInserted(pv, v, result);
    hint = v->cell();
  }
}

void IncrementalState::MergeCoincident(const PendingVertex& pv, VertexHandle existing, MapUpdateResult* result) {
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

namespace {

// Whether the facet of `c` opposite vertex `k` has a frozen vertex: the fans of frozen vertices were fixed
// when they froze (RecordFan), so which of their facets are seen may not change any more.
bool TouchesFrozen(CellHandle c, int k) {
  for (int j = 0; j < 4; ++j) {
    if (j != k && c->vertex(j)->info().frozen) return true;
  }
  return false;
}

constexpr std::size_t kGrainCells = 4096;
// The created cells are voted in blocks of this many spatial neighbours, one view after the other.
constexpr std::size_t kGrainCreatedCells = 256;
// Their spatial order: a Morton code of the centroid on a grid of this step, around the newest camera.
constexpr double kMortonStepM = 0.25;
constexpr double kMortonHalfExtentM = double(1u << 20) * kMortonStepM;
// How many cells ahead the vote loops start fetching the depth map lines a cell's samples will read
// (PrefetchCellDepths): 200 urban frames, PS, half resolution, five pairs against the loops without it: map.votes
// 53.8 → 50.1 ms a frame, the same mesh (bench/RESULTS.md, session 17); 8 cells ahead measured no better.
constexpr std::size_t kPrefetchDepthCells = 4;

// Morton code of a point quantised to `step_m` from `origin` (21 bits per axis): nearby points get nearby
// codes, so cells sorted by it read nearby pixels of each view one after the other.
std::uint64_t MortonCode(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, double step_m) {
  std::uint64_t code = 0;
  std::array<std::uint64_t, 3> q;
  for (int a = 0; a < 3; ++a) {
    q[a] = std::uint64_t(std::clamp((p[a] - origin[a]) / step_m, 0.0, double((1u << 21) - 1)));
  }
  for (int bit = 20; bit >= 0; --bit) {
    for (int a = 0; a < 3; ++a) code = (code << 1) | ((q[a] >> bit) & 1u);
  }
  return code;
}

// Appends the cells of `stamped` to `out` by creation time (CGAL's time stamps, unique). The stamps are read
// once into the keys: a comparison that read them from the cells missed the cache on ~10^5 cells a frame.
void AppendInCreationOrder(std::vector<Stamped>* stamped, std::vector<CellHandle>* out) {
  std::sort(stamped->begin(), stamped->end(),
            [](const Stamped& a, const Stamped& b) { return a.time_stamp < b.time_stamp; });
  for (const Stamped& s : *stamped) out->push_back(s.cell);
}

}  // namespace

std::size_t IncrementalState::VoteCreatedCells(std::size_t created_count) {
  // The cells an insertion created (~15 k a frame) are voted from every view of the window: 8 depth maps of
  // up to 1.8 MB each, more than the caches hold. In cell order each cell read 8 maps at random places and
  // most reads missed the cache; here the cells are sorted in space and, in blocks of neighbours, voted one
  // view at a time, so that consecutive reads fall on the same lines (200 urban frames, PS, half
  // resolution: map.votes 82–96 → 70–76 ms a frame, measured interleaved; bench/RESULTS.md, session 15).
  // The sums are integers: the votes do not depend on the order, and the mesh is the same byte for byte.
  const std::vector<CellHandle>& cells = vote_scratch_.cells;
  if (created_count == 0) return 0;
  std::vector<VoteScratch::Created>& order = vote_scratch_.created_order;
  order.resize(created_count);
  const Eigen::Vector3d origin = views_.back().view->world_from_cam.translation() -
                                 Eigen::Vector3d::Constant(kMortonHalfExtentM);
  ParallelFor(std::size_t(0), created_count, kGrainCells, [&](std::size_t first, std::size_t last) {
    for (std::size_t j = first; j != last; ++j) {
      const CellHandle c = cells[j];
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) centroid += ToEigen(c->vertex(k)->point());
      order[j] = {MortonCode(0.25 * centroid, origin, kMortonStepM), std::uint32_t(j)};
    }
  });
  // Sorted as 16-byte keys (with their vertices they were 112 bytes to move); the vertices are read again per
  // block below.
  std::sort(order.begin(), order.end(), [](const VoteScratch::Created& a, const VoteScratch::Created& b) {
    return a.key != b.key ? a.key < b.key : a.index < b.index;
  });
  std::vector<std::uint8_t>& seen = vote_scratch_.seen;
  std::vector<std::uint8_t>& touched = vote_scratch_.touched;
  const bool track_seen = Emit().drop_unseen;
  std::atomic<std::size_t> voted{0};
  ParallelFor(std::size_t(0), order.size(), kGrainCreatedCells, [&](std::size_t first, std::size_t last) {
    std::size_t voted_here = 0;
    std::array<std::array<Eigen::Vector3d, 4>, kGrainCreatedCells> vertices_block;
    std::array<VoteIncrement, kGrainCreatedCells> fresh_block;
    std::array<std::uint8_t, kGrainCreatedCells> candidates_block;
    for (std::size_t begin = first; begin < last; begin += kGrainCreatedCells) {
      const std::size_t end = std::min(last, begin + kGrainCreatedCells);
      std::array<Eigen::Vector3d, 4>* vertices = vertices_block.data() - begin;
      VoteIncrement* fresh = fresh_block.data() - begin;
      std::uint8_t* candidates = candidates_block.data() - begin;
      for (std::size_t j = begin; j != end; ++j) {
        fresh[j] = {};
        // The facets to look for: every facet (the cell's carving is not known yet) no view saw yet. A facet
        // between two created cells is looked for from the older one only (see LooksFromOtherSide).
        const CellHandle c = cells[order[j].index];
        for (int k = 0; k < 4; ++k) vertices[j][k] = ToEigen(c->vertex(k)->point());
        candidates[j] = 0;
        for (int k = 0; track_seen && k < 4; ++k) {
          if (!FacetSeen(c, k) && !TouchesFrozen(c, k) && !LooksFromOtherSide(c, k)) {
            candidates[j] |= std::uint8_t(1u << k);
          }
        }
      }
      // Each view votes the block's cells and looks for their facets while its depth map's lines are in the
      // cache (newest view first: one view seeing a facet is enough).
      for (auto view = views_.rbegin(); view != views_.rend(); ++view) {
        for (std::size_t j = begin; j != end; ++j) {
          if (j + kPrefetchDepthCells < end) PrefetchCellDepths(vertices[j + kPrefetchDepthCells], *view);
          const VoteIncrement v = VoteCell(vertices[j], *view, depth_geometry_);
          fresh[j].free_q += v.free_q;
          fresh[j].matter_q += v.matter_q;
          if (candidates[j] == 0) continue;
          const std::uint8_t found = SeenFacets(vertices[j], candidates[j], *view, depth_geometry_);
          seen[order[j].index] |= found;
          candidates[j] &= std::uint8_t(~found);
        }
      }
      for (std::size_t j = begin; j != end; ++j) {
        // Seen by the window: its own votes replace the inherited ones (the increment cancels them). Adding
        // them instead let the history of a big parent cell outweigh what the views see of its children
        // (80 urban frames, PS: RMSE vs Velodyne 1.74 → 2.37 m).
        CellInfo& info = cells[order[j].index]->info();
        std::int64_t free_q = 0, matter_q = 0;
        if (fresh[j].free_q != 0 || fresh[j].matter_q != 0) {
          free_q = fresh[j].free_q - info.free_q;
          matter_q = fresh[j].matter_q - info.matter_q;
        }
        voted_here += AddVotes(free_q, matter_q, &info, &touched[order[j].index]);
      }
    }
    voted += voted_here;
  });
  return voted;
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

void IncrementalState::CollectOldCellsInView(const VotingView& view, std::vector<CellHandle>* cells) {
  // A sealed cell never changes: its votes do not matter.
  const auto old_and_unsealed = [&](CellHandle c) {
    return !c->info().IsSealed() && c->info().created != created_mark_;
  };
  std::vector<CellHandle>& walked = vote_scratch_.walk;
  if (CellsInView(dt_, view, NewMark(), &walked)) {
    std::copy_if(walked.begin(), walked.end(), std::back_inserter(*cells), old_and_unsealed);
    return;
  }
  for (auto c = dt_.finite_cells_begin(); c != dt_.finite_cells_end(); ++c) {
    if (old_and_unsealed(c)) cells->push_back(c);
  }
}

bool IncrementalState::AddVotes(std::int64_t free_q, std::int64_t matter_q, CellInfo* info,
                                std::uint8_t* touched) const {
  const bool was_free = info->IsFree();
  const bool has_vote = free_q != 0 || matter_q != 0;
  info->free_q += free_q;
  info->matter_q += matter_q;
  // Changed, or free and still outside the carved region (the manifold test refused it before: retried
  // while the view sees it, as the exact map retries the cells each new ray crosses).
  const bool retry = info->IsFree() && !info->carved && has_vote;
  if ((info->created == created_mark_ || was_free != info->IsFree() || retry) && info->stamp != touch_mark_) {
    info->stamp = touch_mark_;
    *touched = 1;
  }
  return has_vote;
}

std::size_t IncrementalState::VoteFromViews() {
  if (dt_.dimension() < 3 || views_.empty()) return 0;
  // The scratch vectors keep their capacity between frames: the created cells and those in the newest view
  // (~100 k on a street; every live cell, ~650 k on a long drive, when the walk cannot start), which
  // allocated anew (and paged in, and zeroed) every frame cost more than the serial part of the votes.
  // `cells`: the created cells first, then the old ones. A sealed cell never changes: its votes do not
  // matter.
  std::vector<CellHandle>& cells = vote_scratch_.cells;
  cells.clear();
  for (const CellHandle c : created_cells_) {
    if (!dt_.is_infinite(c) && !c->info().IsSealed()) cells.push_back(c);
  }
  const std::size_t first_old = cells.size();
  const VotingView& newest = views_.back();
  CollectOldCellsInView(newest, &cells);
  // Facets seen as a surface (see SeenFacets): every facet of a new cell, in the window's views; on the rest
  // of the map, the surface facets (from their carved side, as carved before this update) of the cells the
  // newest view sees that no view saw yet, in that view.
  const bool track_seen = Emit().drop_unseen;
  std::vector<std::uint8_t>& seen = vote_scratch_.seen;
  seen.assign(track_seen ? cells.size() : 0, 0);
  // Each cell's votes go into its own record, by the thread that computes them: a vote reads the cell's
  // vertices and, for the seen facets, its neighbours' carving and seen bits, never their votes, so the
  // result does not depend on the threads. Which cells are touched is decided there too, and listed below in
  // cell order (deterministic).
  std::vector<std::uint8_t>& touched = vote_scratch_.touched;
  touched.assign(cells.size(), 0);
  std::atomic<std::size_t> voted{VoteCreatedCells(first_old)};
  ParallelFor(first_old, cells.size(), kGrainCells, [&](std::size_t first, std::size_t last) {
    std::size_t voted_here = 0;
    std::array<Eigen::Vector3d, 4> vertices;
    for (std::size_t i = first; i != last; ++i) {
      if (i + kPrefetchCells < last) {
        const CellHandle ahead = cells[i + kPrefetchCells];
        for (int k = 0; k < 4; ++k) __builtin_prefetch(&*ahead->vertex(k));
      }
      if (i + kPrefetchDepthCells < last) {
        const CellHandle ahead = cells[i + kPrefetchDepthCells];
        std::array<Eigen::Vector3d, 4> ahead_vertices;
        for (int k = 0; k < 4; ++k) ahead_vertices[k] = ToEigen(ahead->vertex(k)->point());
        PrefetchCellDepths(ahead_vertices, newest);
      }
      const CellHandle c = cells[i];
      for (int k = 0; k < 4; ++k) vertices[k] = ToEigen(c->vertex(k)->point());
      const VoteIncrement vote = VoteCell(vertices, newest, depth_geometry_);
      voted_here += AddVotes(vote.free_q, vote.matter_q, &c->info(), &touched[i]);
      // An old cell the newest view does not see has no facet it could see.
      if (!track_seen || !vote.in_view || !c->info().carved) continue;
      std::uint8_t candidates = 0;
      for (int k = 0; k < 4; ++k) {
        if (!NeighbourCarved(c, k) && !FacetSeen(c, k) && !TouchesFrozen(c, k)) {
          candidates |= std::uint8_t(1u << k);
        }
      }
      if (candidates != 0) seen[i] = SeenFacets(vertices, candidates, newest, depth_geometry_);
    }
    voted += voted_here;
  });
  // The seen bits go on both sides of a facet, so they are set in one thread.
  newly_seen_.clear();
  std::vector<Stamped>& touched_stamped = vote_scratch_.touched_stamped;
  std::vector<Stamped>& seen_stamped = vote_scratch_.seen_stamped;
  touched_stamped.clear();
  seen_stamped.clear();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (touched[i]) touched_stamped.push_back({cells[i]->time_stamp(), cells[i]});
    if (!track_seen || seen[i] == 0) continue;
    seen_stamped.push_back({cells[i]->time_stamp(), cells[i]});
    for (int k = 0; k < 4; ++k) {
      if ((seen[i] >> k) & 1) MarkFacetSeen(cells[i], k);
    }
  }
  // In creation order, whatever order the cells were found in: the carving takes them in this order.
  AppendInCreationOrder(&touched_stamped, &touched_);
  AppendInCreationOrder(&seen_stamped, &newly_seen_);
  counters_.cells_visited += voted;
  return voted.load();
}

}  // namespace semap::map_internal
