#include "engine/map/internal/manifold_carver.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

#include "engine/core/check.h"

namespace semap::map_internal {
namespace {

constexpr int kNeighbourShift = 56;
constexpr std::int64_t kMaxVoteKey = (std::int64_t(1) << kNeighbourShift) - 1;

}  // namespace

bool ManifoldCarver::IsRegular(VertexHandle v) {
  ++num_tests_;
  cells_.clear();
  edges_.clear();
  dt_->incident_cells(v, std::back_inserter(cells_));
  for (const CellHandle c : cells_) {
    if (!c->info().carved) continue;
    const int iv = c->index(v);
    for (int i = 0; i < 4; ++i) {
      if (i == iv || c->neighbor(i)->info().carved) continue;
      // Boundary facet opposite i: its link edge joins the two vertices other than v and c->vertex(i).
      VertexHandle ends[2];
      int n = 0;
      for (int k = 0; k < 4; ++k) {
        if (k != iv && k != i) ends[n++] = c->vertex(k);
      }
      edges_.emplace_back(ends[0], ends[1]);
    }
  }
  if (edges_.empty()) return true;
  // Every link vertex must have exactly two boundary edges...
  ends_.clear();
  for (const auto& [a, b] : edges_) {
    ends_.push_back(a);
    ends_.push_back(b);
  }
  // By address: only equal ends must meet, and VertexHandle's operator< compares CGAL's time stamps, a load
  // from each vertex (scattered over the map) per comparison.
  std::sort(ends_.begin(), ends_.end(), [](VertexHandle a, VertexHandle b) { return &*a < &*b; });
  for (std::size_t i = 0; i < ends_.size(); i += 2) {
    if (ends_[i] != ends_[i + 1] || (i + 2 < ends_.size() && ends_[i + 2] == ends_[i])) return false;
  }
  // ...and the edges must form one cycle, not several.
  const VertexHandle start = edges_[0].first;
  VertexHandle current = edges_[0].second;
  std::size_t previous = 0, steps = 1;
  while (current != start) {
    std::size_t next = edges_.size();
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      if (e != previous && (edges_[e].first == current || edges_[e].second == current)) {
        next = e;
        break;
      }
    }
    if (next == edges_.size()) return false;
    current = edges_[next].first == current ? edges_[next].second : edges_[next].first;
    previous = next;
    ++steps;
  }
  return steps == edges_.size();
}

// The link of a vertex v is a triangulated sphere; the carved cells around v are a set K of its triangles,
// and v is regular iff K is empty, the whole sphere or a closed disk (its boundary one simple cycle). Carving
// a cell c adds one triangle t to K; its three edges are shared with the link triangles of the three
// neighbours of c across the facets through v. With K regular before and E of those edges already in K:
//  - E = 3: t was the whole complement of K, K ∪ t is the sphere: regular;
//  - E = 2: t is glued along two consecutive boundary edges of the disk K: still a disk, regular;
//  - E = 1: t is glued along one boundary edge; a disk iff the opposite link vertex w of t is not in K
//    (otherwise the boundary would touch itself at w), i.e. no carved cell around the edge (v, w);
//  - E = 0: not regular if a vertex of t is in K (pinch); otherwise regular iff K is empty, which needs the
//    whole star: left to IsRegular.
ManifoldCarver::Verdict ManifoldCarver::CarveVerdict(CellHandle cell, int iv) const {
  int carved_edges = 0;
  for (int j = 0; j < 4; ++j) {
    if (j == iv) continue;
    if (cell->neighbor(j)->info().carved) ++carved_edges;
  }
  if (carved_edges >= 2) return Verdict::kRegular;
  if (carved_edges == 1) {
    // The carved neighbour is across the facet opposite w; w is the vertex opposite that facet.
    for (int j = 0; j < 4; ++j) {
      if (j == iv || !cell->neighbor(j)->info().carved) continue;
      return EdgeTouchesCarved(cell, iv, j) ? Verdict::kNotRegular : Verdict::kRegular;
    }
  }
  for (int j = 0; j < 4; ++j) {
    if (j != iv && EdgeTouchesCarved(cell, iv, j)) return Verdict::kNotRegular;
  }
  return Verdict::kUnknown;
}

bool ManifoldCarver::EdgeTouchesCarved(CellHandle cell, int i, int j) const {
  const Delaunay::Cell_circulator start = dt_->incident_cells(cell, i, j);
  Delaunay::Cell_circulator c = start;
  do {
    if (c->info().carved) return true;
  } while (++c != start);
  return false;
}

bool ManifoldCarver::TryCarve(CellHandle cell) {
  if (cell->info().carved || dt_->is_infinite(cell) || IsPinned(cell)) return false;
  // Every vertex is regular before (the carver's invariant), so the local verdicts decide most cases.
  VertexHandle unknown[4];
  int num_unknown = 0;
  for (int k = 0; k < 4; ++k) {
    switch (CarveVerdict(cell, k)) {
      case Verdict::kNotRegular:
        ++num_tests_;
        return false;
      case Verdict::kUnknown:
        unknown[num_unknown++] = cell->vertex(k);
        break;
      case Verdict::kRegular:
        ++num_tests_;
        break;
    }
  }
  cell->info().carved = true;
  for (int k = 0; k < num_unknown; ++k) {
    if (!IsRegular(unknown[k])) {
      cell->info().carved = false;
      return false;
    }
  }
  return true;
}

std::size_t ManifoldCarver::Grow(const std::vector<CellHandle>& candidates,
                                 std::vector<CellHandle>* carved_cells) {
  using Entry = std::pair<std::int64_t, CellHandle>;
  auto lower = [](const Entry& a, const Entry& b) { return a.first < b.first; };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower)> queue(lower);
  // Cells closing more of the region (more carved neighbours) first, then by free vote: a cell with several
  // carved facets rarely pinches the surface, while growing thin fingers first blocks later additions.
  auto push = [&](CellHandle c) {
    if (c->info().carved || !c->info().IsFree() || dt_->is_infinite(c) || IsPinned(c)) return;
    std::int64_t carved_neighbours = 0;
    for (int i = 0; i < 4; ++i) carved_neighbours += c->neighbor(i)->info().carved ? 1 : 0;
    queue.emplace((carved_neighbours << kNeighbourShift) + std::min(c->info().free_q, kMaxVoteKey), c);
  };
  for (const CellHandle c : candidates) push(c);
  std::size_t carved = 0;
  std::vector<CellHandle> failed;
  for (int pass = 0; pass < max_passes_; ++pass) {
    std::size_t carved_in_pass = 0;
    while (!queue.empty()) {
      const CellHandle c = queue.top().second;
      queue.pop();
      if (!TryCarve(c)) {
        failed.push_back(c);
        continue;
      }
      ++carved_in_pass;
      if (carved_cells != nullptr) carved_cells->push_back(c);
      for (int i = 0; i < 4; ++i) push(c->neighbor(i));
    }
    carved += carved_in_pass;
    if (carved_in_pass == 0 || failed.empty()) break;
    // A failed cell may have become carvable through cells carved around its vertices (not only through its
    // neighbours): retry them all once more.
    for (const CellHandle c : failed) push(c);
    failed.clear();
  }
  return carved;
}

void ManifoldCarver::Repair(std::vector<VertexHandle> vertices, bool allow_fill,
                            std::vector<CellHandle>* changed) {
  settled_.clear();
  // A repair step pushes the vertices of every cell it changes, so a vertex is often on the stack many times
  // (63 % of the pops on 200 urban frames). A vertex found regular stays so until a cell around it changes,
  // which pushes it again: until then its copies are passed over without a test.
  regular_.clear();
  std::vector<VertexHandle> stack = std::move(vertices);
  while (!stack.empty()) {
    const VertexHandle v = stack.back();
    stack.pop_back();
    // A frozen vertex's star is pinned: its fan is final (and made regular before it froze).
    if (dt_->is_infinite(v) || v->info().frozen || regular_.count(&*v)) continue;
    bool regular = true;
    while (!IsRegular(v)) {
      const std::size_t pushed = stack.size();
      if (!RepairStep(v, allow_fill && fill_cost_q_ >= 0, &stack, changed)) {
        ++num_unrepaired_;
        unrepaired_.push_back(v);
        regular = false;
        break;
      }
      for (std::size_t k = pushed; k < stack.size(); ++k) regular_.erase(&*stack[k]);
    }
    if (regular) regular_.insert(&*v);
  }
  settled_.clear();
  regular_.clear();
}

bool ManifoldCarver::RepairStep(VertexHandle v, bool allow_fill, std::vector<VertexHandle>* stack,
                                std::vector<CellHandle>* changed) {
  auto set_carved = [&](CellHandle c, bool carved) {
    c->info().carved = carved;
    settled_.insert(&*c);
    changed->push_back(c);
    for (int k = 0; k < 4; ++k) stack->push_back(c->vertex(k));
  };
  auto excess = [](CellHandle c) { return c->info().free_q - c->info().matter_q; };
  star_.clear();
  dt_->incident_cells(v, std::back_inserter(star_));
  // Facet-connected components of the carved cells around v (through facets incident to v).
  const int n = int(star_.size());
  component_.assign(n, -1);
  auto index_of = [&](CellHandle c) { return int(std::find(star_.begin(), star_.end(), c) - star_.begin()); };
  std::vector<std::int64_t> component_excess;
  for (int s = 0; s < n; ++s) {
    if (!star_[s]->info().carved || component_[s] >= 0) continue;
    const int id = int(component_excess.size());
    component_excess.push_back(0);
    std::vector<int> todo{s};
    component_[s] = id;
    while (!todo.empty()) {
      const CellHandle c = star_[todo.back()];
      todo.pop_back();
      component_excess[id] += excess(c);
      const int iv = c->index(v);
      for (int i = 0; i < 4; ++i) {
        if (i == iv || !c->neighbor(i)->info().carved) continue;
        const int t = index_of(c->neighbor(i));
        if (t < n && component_[t] < 0) {
          component_[t] = id;
          todo.push_back(t);
        }
      }
    }
  }
  SEMAP_ASSERT(!component_excess.empty(), "a vertex without carved cells is regular");
  // A component holding a pinned cell cannot be given up: it is the one kept, and with two such
  // components keeping is impossible.
  int best =
      int(std::max_element(component_excess.begin(), component_excess.end()) - component_excess.begin());
  int pinned_components = 0;
  {
    std::vector<char> has_pinned(component_excess.size(), 0);
    for (int s = 0; s < n; ++s) {
      if (component_[s] >= 0 && !has_pinned[component_[s]] && IsPinned(star_[s])) {
        has_pinned[component_[s]] = 1;
        ++pinned_components;
        best = component_[s];
      }
    }
  }
  constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
  std::int64_t keep_cost = kNever;
  if (component_excess.size() > 1 && pinned_components <= 1) {
    keep_cost = 0;
    for (int s = 0; s < n; ++s) {
      if (component_[s] >= 0 && component_[s] != best)
        keep_cost += std::max<std::int64_t>(excess(star_[s]), 0);
    }
  }
  std::int64_t fill_cost = allow_fill ? 0 : kNever;
  for (int s = 0; s < n && fill_cost != kNever; ++s) {
    const CellHandle c = star_[s];
    if (c->info().carved) continue;
    if (dt_->is_infinite(c) || settled_.count(&*c) || IsPinned(c)) {
      fill_cost = kNever;
    } else {
      fill_cost += std::max<std::int64_t>(-excess(c), 0) + fill_cost_q_;
    }
  }
  if (fill_cost < keep_cost) {
    for (int s = 0; s < n; ++s) {
      if (!star_[s]->info().carved) set_carved(star_[s], true);
    }
  } else if (keep_cost != kNever) {
    for (int s = 0; s < n; ++s) {
      if (component_[s] >= 0 && component_[s] != best) set_carved(star_[s], false);
    }
  } else {
    // One component that pinches itself: give up its weakest cell with an uncarved neighbour around v.
    int weakest = -1;
    for (int s = 0; s < n; ++s) {
      const CellHandle c = star_[s];
      if (!c->info().carved) continue;
      const int iv = c->index(v);
      bool on_boundary = false;
      for (int i = 0; i < 4; ++i) on_boundary |= i != iv && !c->neighbor(i)->info().carved;
      if (on_boundary && !IsPinned(c) && (weakest < 0 || excess(c) < excess(star_[weakest]))) weakest = s;
    }
    // Without pinned cells a non-regular vertex always has a carved cell on the boundary; beside a seam of
    // finalisation every such cell may be pinned, and nothing is left to change here.
    if (weakest < 0) return false;
    set_carved(star_[weakest], false);
  }
  return true;
}

void ManifoldCarver::SortByPosition(std::vector<VertexHandle>* vertices) {
  // A geometric order (not the handles' addresses), so that the same cells give the same repair in any
  // triangulation holding them (the batch and the incremental map). The coordinates are copied into the keys
  // once, after the repeats are gone (found by sorting the handles as addresses, which reads nothing; not
  // VertexHandle's operator<, which compares creation time stamps read from the vertices). The vertices of
  // ~15 k carved cells are ~50 k handles of ~6 k vertices a frame; their sort by a comparison that read the
  // coordinates from the vertices took 1.7 % of a run's CPU (200 urban frames, half resolution).
  std::sort(vertices->begin(), vertices->end(),
            [](VertexHandle a, VertexHandle b) { return std::less<const void*>()(&*a, &*b); });
  vertices->erase(std::unique(vertices->begin(), vertices->end()), vertices->end());
  std::vector<PositionKey>& keys = position_keys_;
  keys.clear();
  for (const VertexHandle v : *vertices)
    keys.push_back({{v->point().x(), v->point().y(), v->point().z()}, v});
  std::sort(keys.begin(), keys.end(),
            [](const PositionKey& a, const PositionKey& b) { return a.xyz < b.xyz; });
  for (std::size_t i = 0; i < keys.size(); ++i) (*vertices)[i] = keys[i].vertex;
}

std::size_t ManifoldCarver::CarveAndRepair(const std::vector<CellHandle>& cells,
                                           std::vector<CellHandle>* changed,
                                           const std::vector<VertexHandle>& also_repair) {
  std::vector<VertexHandle> vertices = also_repair;
  std::size_t carved = 0;
  for (const CellHandle c : cells) {
    if (c->info().carved || !c->info().IsFree() || dt_->is_infinite(c) || IsPinned(c)) continue;
    c->info().carved = true;
    ++carved;
    for (int k = 0; k < 4; ++k) vertices.push_back(c->vertex(k));
  }
  SortByPosition(&vertices);
  Repair(std::move(vertices), /*allow_fill=*/true, changed);
  return carved + Grow(cells, changed);
}

void ManifoldCarver::UncarveStars(const std::vector<VertexHandle>& vertices,
                                  std::vector<CellHandle>* uncarved) {
  std::vector<VertexHandle> to_check;
  std::vector<CellHandle> star;
  for (const VertexHandle v : vertices) {
    star.clear();
    dt_->incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (!c->info().carved || IsPinned(c)) continue;
      c->info().carved = false;
      uncarved->push_back(c);
      for (int k = 0; k < 4; ++k) to_check.push_back(c->vertex(k));
    }
  }
  Repair(std::move(to_check), /*allow_fill=*/false, uncarved);
}

}  // namespace semap::map_internal
