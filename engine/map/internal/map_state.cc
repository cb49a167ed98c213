#include "engine/map/internal/map_state.h"

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <numeric>

#include "engine/core/check.h"

namespace semap::map_internal {

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

MapState::MapState(const MapOptions& map_options, const EmitRule& emit)
    : options(map_options),
      lattice(map_options.steiner_spacing_m, map_options.steiner_margin_cubes),
      mesher(&dt, emit, [this](VertexHandle v) { return OutputPosition(v); }) {}

void MapState::BeginUpdate() {
  update.nodes.clear();
  update.created_mark = NewMark();
}

void MapState::BeginFrame(const LabelledCloud& frame_points) {
  BeginUpdate();
  ++frame;
  for (const Eigen::Vector3d& c : frame_points.camera_centers_world) {
    lattice.Use(c, frame, &update.nodes);
    last_camera = c;
  }
}

void MapState::AddSteinerNodes(std::vector<PendingVertex>* pending) {
  for (const PendingVertex& p : *pending) lattice.Use(p.position, frame, &update.nodes);
  for (LatticeKey node : update.nodes) pending->push_back({lattice.Position(node), kNoId, node, {}});
  SpatialSort(pending);
}

std::uint32_t MapState::NewPoint(const LabelledCloud& frame_points, std::uint32_t i,
                                 std::vector<PendingVertex>* pending) {
  const std::uint32_t id = next_point_id++;
  PointRecord& record = points[id];
  record.position = frame_points.positions_world[i];
  record.last_seen = frame;
  pending->push_back({record.position, id, 0, AttributesOf(frame_points, i)});
  return id;
}

void MapState::InsertVertices(std::vector<PendingVertex>* pending, MapUpdateResult* result) {
  update.inserted.clear();
  VertexHandle previous;
  for (const PendingVertex& pv : *pending) {
    const std::size_t before = dt.number_of_vertices();
    const VertexHandle v =
        dt.insert(ToPoint(pv.position), previous == VertexHandle() ? CellHandle() : previous->cell());
    SEMAP_ASSERT(dt.number_of_vertices() == before + 1,
                 "vertex at an occupied position " << pv.position.transpose());
    RecordInserted(pv, v, result);
    previous = v;
  }
}

void MapState::RecordInserted(const PendingVertex& pv, VertexHandle v, MapUpdateResult* result) {
  if (pv.point_id != kNoId) {
    v->info() = VertexInfo{pv.point_id, false, false, 0, 0, pv.attributes};
    PointRecord& record = points.at(pv.point_id);
    record.vertex = v;
    arrival.push_back({pv.point_id, record.last_seen});
    ++result->inserted;
  } else {
    v->info() = VertexInfo{next_steiner_id++, true, false, 0, 0, {}};
    steiner[pv.node] = v;
    ++result->steiner_inserted;
  }
  update.inserted.push_back(v);
}

std::size_t MapState::DropPinnedConflicts(const std::vector<char>& conflicts_pinned,
                                          std::vector<PendingVertex>* pending, MapUpdateResult* result,
                                          std::unordered_set<std::uint32_t>* dropped_ids) {
  dropped_ids->clear();
  std::size_t kept = 0;
  for (std::size_t k = 0; k < pending->size(); ++k) {
    PendingVertex& pv = (*pending)[k];
    if (!conflicts_pinned[k]) {
      (*pending)[kept++] = std::move(pv);
    } else if (pv.point_id != kNoId) {
      dropped_ids->insert(pv.point_id);
      points.erase(pv.point_id);
    }
    // A dropped Steiner node stays "required" in the lattice but absent: Finalise skips it.
  }
  pending->resize(kept);
  if (dropped_ids->empty()) return 0;
  std::size_t dropped = 0;  // frame points: the new points and those merged into them
  for (std::uint32_t& id : result->point_ids) {
    if (id == kDroppedPoint || !dropped_ids->count(id)) continue;
    id = kDroppedPoint;
    ++dropped;
  }
  result->merged -= dropped - dropped_ids->size();
  result->dropped += dropped;
  return dropped;
}

void MapState::BeginTouched() {
  update.touched.clear();
  update.touch_mark = NewMark();
}

void MapState::Touch(CellHandle c) {
  if (c->info().stamp == update.touch_mark) return;
  c->info().stamp = update.touch_mark;
  update.touched.push_back(c);
}

void MapState::MarkCreatedCells(const std::vector<VertexHandle>& vertices, std::uint32_t old_mark,
                                std::vector<CellHandle>* newly_marked) {
  std::vector<CellHandle> star;
  for (const VertexHandle v : vertices) {
    star.clear();
    dt.incident_cells(v, std::back_inserter(star));
    for (const CellHandle c : star) {
      if (c->info().stamp == old_mark || c->info().created == update.created_mark) continue;
      c->info().created = update.created_mark;
      if (newly_marked != nullptr) newly_marked->push_back(c);
    }
  }
}

std::uint32_t MapState::StampCellsAround(const std::vector<VertexHandle>& vertices) {
  const std::uint32_t mark = NewMark();
  std::vector<CellHandle> around;
  for (const VertexHandle v : vertices) {
    around.clear();
    dt.incident_cells(v, std::back_inserter(around));
    for (const CellHandle c : around) c->info().stamp = mark;
  }
  return mark;
}

void MapState::CollectBoundary(std::uint32_t excluded_vertex_mark) {
  update.boundary.clear();
  const std::uint32_t mark = NewMark();
  for (const CellHandle c : update.destroyed) AddVerticesToBoundary(c, mark, excluded_vertex_mark);
}

void MapState::AddVerticesToBoundary(CellHandle c, std::uint32_t mark, std::uint32_t excluded_vertex_mark) {
  for (int k = 0; k < 4; ++k) {
    const VertexHandle v = c->vertex(k);
    if (dt.is_infinite(v) || v->info().stamp == mark || v->info().stamp == excluded_vertex_mark) continue;
    v->info().stamp = mark;
    update.boundary.push_back(v);
  }
}

void MapState::AddToBoundary(const std::vector<VertexHandle>& vertices) {
  const std::uint32_t mark = NewMark();
  for (const VertexHandle v : update.boundary) v->info().stamp = mark;
  for (const VertexHandle v : vertices) {
    if (v->info().stamp == mark) continue;
    v->info().stamp = mark;
    update.boundary.push_back(v);
  }
}

Eigen::Vector3d MapState::OutputPosition(VertexHandle v) const {
  if (v->info().steiner || v->info().output_version == 0) return ToEigen(v->point());
  return points.at(v->info().id).output_position;
}

MapStatistics MapState::Sizes() const {
  MapStatistics s = counters;
  s.num_points = points.size();
  s.num_steiner_vertices = steiner.size();
  // number_of_finite_cells() walks every cell; all cells less the infinite ones (those around the hull) is
  // the same count, read off in O(hull).
  if (dt.dimension() == 3) {
    std::vector<CellHandle> infinite;
    dt.incident_cells(dt.infinite_vertex(), std::back_inserter(infinite));
    s.num_cells = dt.number_of_cells() - infinite.size();
  }
  return s;
}

}  // namespace semap::map_internal
