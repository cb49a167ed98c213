#include "engine/map/internal/depth_integrator.h"

#include <algorithm>
#include <atomic>

#include "engine/core/parallel.h"
#include "engine/map/internal/surface_extraction.h"

namespace semap::map_internal {

namespace {

// Whether the facet of `c` opposite vertex `k` has a frozen vertex: the fans of frozen vertices were fixed
// when they froze (Mesher::RecordFan), so which of their facets are seen may not change any more.
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
// (PrefetchCellDepths): 200 urban frames, PS, half resolution, five pairs against the loops without it:
// map.votes 53.8 → 50.1 ms a frame, the same mesh (bench/results/frame-rate.md, "Depth lines prefetched in
// the vote loops"); 8 cells ahead measured no better.
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

DepthIntegrator::DepthIntegrator(Delaunay* dt, const MapOptions& options)
    : dt_(dt),
      geometry_(options),
      window_frames_(std::size_t(options.vote_window_frames)),
      seen_window_frames_(std::size_t(options.seen_window_frames)),
      track_seen_(options.drop_unseen_surface) {}

void DepthIntegrator::AddFrame(const std::vector<std::shared_ptr<const DepthView>>& views) {
  for (const auto& view : views) views_.emplace_back(view);
  while (views_.size() > window_frames_ * std::max<std::size_t>(1, views.size())) views_.pop_front();
  for (const auto& view : views) seen_views_.emplace_back(view);
  while (seen_views_.size() > seen_window_frames_ * std::max<std::size_t>(1, views.size()))
    seen_views_.pop_front();
}

std::size_t DepthIntegrator::VoteCreatedCells(std::size_t created_count) {
  // The cells an insertion created (~15 k a frame) are voted from every view of the window: 8 depth maps of
  // up to 1.8 MB each, more than the caches hold. In cell order each cell read 8 maps at random places and
  // most reads missed the cache; here the cells are sorted in space and, in blocks of neighbours, voted one
  // view at a time, so that consecutive reads fall on the same lines (200 urban frames, PS, half
  // resolution: map.votes 82–96 → 70–76 ms a frame, measured interleaved; bench/results/frame-rate.md,
  // "What changed, one commit at a time").
  // The sums are integers: the votes do not depend on the order, and the mesh is the same byte for byte.
  const std::vector<CellHandle>& cells = scratch_.cells;
  if (created_count == 0) return 0;
  std::vector<Scratch::Created>& order = scratch_.created_order;
  order.resize(created_count);
  const Eigen::Vector3d origin =
      views_.back().view->world_from_cam.translation() - Eigen::Vector3d::Constant(kMortonHalfExtentM);
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
  std::sort(order.begin(), order.end(), [](const Scratch::Created& a, const Scratch::Created& b) {
    return a.key != b.key ? a.key < b.key : a.index < b.index;
  });
  std::vector<std::uint8_t>& touched = scratch_.touched;
  std::atomic<std::size_t> voted{0};
  ParallelFor(std::size_t(0), order.size(), kGrainCreatedCells, [&](std::size_t first, std::size_t last) {
    std::size_t voted_here = 0;
    std::array<std::array<Eigen::Vector3d, 4>, kGrainCreatedCells> vertices_block;
    std::array<VoteIncrement, kGrainCreatedCells> fresh_block;
    for (std::size_t begin = first; begin < last; begin += kGrainCreatedCells) {
      const std::size_t end = std::min(last, begin + kGrainCreatedCells);
      std::array<Eigen::Vector3d, 4>* vertices = vertices_block.data() - begin;
      VoteIncrement* fresh = fresh_block.data() - begin;
      for (std::size_t j = begin; j != end; ++j) {
        fresh[j] = {};
        const CellHandle c = cells[order[j].index];
        for (int k = 0; k < 4; ++k) vertices[j][k] = ToEigen(c->vertex(k)->point());
      }
      // Each view votes the block's cells while its depth map's lines are in the cache.
      for (auto view = views_.rbegin(); view != views_.rend(); ++view) {
        for (std::size_t j = begin; j != end; ++j) {
          if (j + kPrefetchDepthCells < end) PrefetchCellDepths(vertices[j + kPrefetchDepthCells], *view);
          const VoteIncrement v = VoteCell(vertices[j], *view, geometry_);
          fresh[j].free_q += v.free_q;
          fresh[j].matter_q += v.matter_q;
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

void DepthIntegrator::CollectOldCellsInView(const VotingView& view, std::vector<CellHandle>* cells) {
  // A sealed cell never changes: its votes do not matter.
  const auto old_and_unsealed = [&](CellHandle c) {
    return !c->info().IsSealed() && c->info().created != marks_.created;
  };
  std::vector<CellHandle>& walked = scratch_.walk;
  if (CellsInView(*dt_, view, marks_.visit, &walked)) {
    std::copy_if(walked.begin(), walked.end(), std::back_inserter(*cells), old_and_unsealed);
    return;
  }
  for (auto c = dt_->finite_cells_begin(); c != dt_->finite_cells_end(); ++c) {
    if (old_and_unsealed(c)) cells->push_back(c);
  }
}

std::size_t DepthIntegrator::MarkSeenSurface(const std::vector<CellHandle>& listed, std::uint32_t list_mark,
                                             std::vector<CellHandle>* newly_seen) {
  if (!track_seen_ || views_.empty() || dt_->dimension() < 3) return 0;
  const auto looked_at = [&](CellHandle c) { return !dt_->is_infinite(c) && !c->info().IsSealed(); };
  std::vector<CellHandle>& cells = scratch_.surface_cells;
  cells.clear();
  for (const CellHandle c : listed) {
    if (!looked_at(c) || c->info().stamp == list_mark) continue;
    c->info().stamp = list_mark;
    cells.push_back(c);
  }
  std::vector<std::uint8_t>& seen = scratch_.seen;
  seen.assign(cells.size(), 0);
  ParallelFor(std::size_t(0), cells.size(), kGrainCreatedCells, [&](std::size_t first, std::size_t last) {
    std::array<Eigen::Vector3d, 4> vertices;
    for (std::size_t j = first; j != last; ++j) {
      if (j + kPrefetchCells < last) PrefetchNeighbourRecords(cells[j + kPrefetchCells]);
      const CellHandle c = cells[j];
      const bool carved_here = c->info().carved;
      std::uint8_t candidates = 0;
      for (int k = 0; k < 4; ++k) {
        const CellHandle n = c->neighbor(k);
        if (carved_here == NeighbourCarved(c, k)) continue;  // not a surface facet
        // A facet between two listed cells is looked for from its carved side only.
        if (!carved_here && looked_at(n) && n->info().stamp == list_mark) continue;
        if (!FacetSeen(c, k) && !TouchesFrozen(c, k)) candidates |= std::uint8_t(1u << k);
      }
      if (candidates == 0) continue;
      for (int k = 0; k < 4; ++k) vertices[k] = ToEigen(c->vertex(k)->point());
      for (auto view = seen_views_.rbegin(); view != seen_views_.rend() && candidates != 0; ++view) {
        const std::uint8_t found = SeenFacets(vertices, candidates, *view, geometry_);
        seen[j] |= found;
        candidates &= std::uint8_t(~found);
      }
    }
  });
  // The seen bits go on both sides of a facet, so they are set in one thread.
  std::vector<Stamped>& seen_stamped = scratch_.seen_stamped;
  seen_stamped.clear();
  std::size_t marked = 0;
  for (std::size_t j = 0; j < cells.size(); ++j) {
    if (seen[j] == 0) continue;
    seen_stamped.push_back({cells[j]->time_stamp(), cells[j]});
    for (int k = 0; k < 4; ++k) {
      if ((seen[j] >> k) & 1) {
        MarkFacetSeen(cells[j], k);
        ++marked;
      }
    }
  }
  AppendInCreationOrder(&seen_stamped, newly_seen);
  return marked;
}

bool DepthIntegrator::AddVotes(std::int64_t free_q, std::int64_t matter_q, CellInfo* info,
                               std::uint8_t* touched) const {
  const bool was_free = info->IsFree();
  const bool has_vote = free_q != 0 || matter_q != 0;
  info->free_q += free_q;
  info->matter_q += matter_q;
  // Changed, or free and still outside the carved region (the manifold test refused it before: retried
  // while the view sees it, as the exact map retries the cells each new ray crosses).
  const bool retry = info->IsFree() && !info->carved && has_vote;
  if ((info->created == marks_.created || was_free != info->IsFree() || retry) &&
      info->stamp != marks_.touch) {
    info->stamp = marks_.touch;
    *touched = 1;
  }
  return has_vote;
}

std::size_t DepthIntegrator::Integrate(const std::vector<CellHandle>& created, const Marks& marks,
                                       std::vector<CellHandle>* touched_cells,
                                       std::vector<CellHandle>* newly_seen) {
  marks_ = marks;
  if (dt_->dimension() < 3 || views_.empty()) return 0;
  // `cells` (scratch_, see there): the created cells first, then the old ones. A sealed cell never changes:
  // its votes do not matter.
  std::vector<CellHandle>& cells = scratch_.cells;
  cells.clear();
  for (const CellHandle c : created) {
    if (!dt_->is_infinite(c) && !c->info().IsSealed()) cells.push_back(c);
  }
  const std::size_t first_old = cells.size();
  const VotingView& newest = views_.back();
  if (marks.newest_view) CollectOldCellsInView(newest, &cells);
  // Facets seen as a surface (see SeenFacets): the surface facets (from their carved side, as carved before
  // this update) of the old cells the newest view sees that no view saw yet, in that view. The created cells'
  // surface facets are looked for after the carving (MarkSeenSurface).
  std::vector<std::uint8_t>& seen = scratch_.seen;
  seen.assign(track_seen_ ? cells.size() : 0, 0);
  // Each cell's votes go into its own record, by the thread that computes them: a vote reads the cell's
  // vertices and, for the seen facets, its neighbours' carving and seen bits, never their votes, so the
  // result does not depend on the threads. Which cells are touched is decided there too, and listed below in
  // cell order (deterministic).
  std::vector<std::uint8_t>& touched = scratch_.touched;
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
      const VoteIncrement vote = VoteCell(vertices, newest, geometry_);
      voted_here += AddVotes(vote.free_q, vote.matter_q, &c->info(), &touched[i]);
      // An old cell the newest view does not see has no facet it could see.
      if (!track_seen_ || !vote.in_view || !c->info().carved) continue;
      std::uint8_t candidates = 0;
      for (int k = 0; k < 4; ++k) {
        if (!NeighbourCarved(c, k) && !FacetSeen(c, k) && !TouchesFrozen(c, k)) {
          candidates |= std::uint8_t(1u << k);
        }
      }
      if (candidates != 0) seen[i] = SeenFacets(vertices, candidates, newest, geometry_);
    }
    voted += voted_here;
  });
  // The seen bits go on both sides of a facet, so they are set in one thread.
  std::vector<Stamped>& touched_stamped = scratch_.touched_stamped;
  std::vector<Stamped>& seen_stamped = scratch_.seen_stamped;
  touched_stamped.clear();
  seen_stamped.clear();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (touched[i]) touched_stamped.push_back({cells[i]->time_stamp(), cells[i]});
    if (!track_seen_ || seen[i] == 0) continue;
    seen_stamped.push_back({cells[i]->time_stamp(), cells[i]});
    for (int k = 0; k < 4; ++k) {
      if ((seen[i] >> k) & 1) MarkFacetSeen(cells[i], k);
    }
  }
  // In creation order, whatever order the cells were found in: the carving takes them in this order.
  AppendInCreationOrder(&touched_stamped, touched_cells);
  AppendInCreationOrder(&seen_stamped, newly_seen);
  return voted.load();
}

}  // namespace semap::map_internal
