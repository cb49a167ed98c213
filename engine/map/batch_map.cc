#include "engine/map/batch_map.h"

#include <unordered_map>

#include "engine/core/check.h"
#include "engine/map/internal/manifold_carver.h"
#include "engine/map/internal/ray_tracer.h"
#include "engine/map/internal/steiner_lattice.h"
#include "engine/map/internal/surface_extraction.h"

namespace semap {

using namespace map_internal;

namespace {

bool WithinRange(const MapOptions& o, const Eigen::Vector3d& p, const Eigen::Vector3d& camera) {
  return o.max_ray_length_m <= 0.0 || (p - camera).norm() <= o.max_ray_length_m;
}

}  // namespace

BatchMapResult BuildBatchMap(const MapOptions& options, const LabelledCloud& cloud,
                             const std::vector<Observation>& extra_observations, bool with_cell_votes) {
  options.Check();
  cloud.AssertConsistent();
  SEMAP_ASSERT(!cloud.camera_centers_world.empty() && cloud.camera_index.size() == cloud.size(),
               "the batch map needs cameras and a first camera per point");
  BatchMapResult result;

  // Points (kept ones) and Steiner nodes, inserted together (CGAL sorts them spatially).
  SteinerLattice lattice(options.steiner_spacing_m, options.steiner_margin_cubes);
  std::vector<LatticeKey> nodes;
  std::vector<std::pair<Point, VertexInfo>> inputs;
  inputs.reserve(cloud.size());
  std::vector<bool> kept(cloud.size(), false);
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud.positions_world[i];
    if (!WithinRange(options, p, cloud.camera_centers_world[cloud.camera_index[i]])) continue;
    kept[i] = true;
    lattice.Use(p, 0, &nodes);
    VertexInfo info{i, false, false, 0, {}};
    if (!cloud.labels.empty()) info.attributes.label = cloud.labels[i];
    if (!cloud.colors_rgb.empty()) info.attributes.color_rgb = cloud.colors_rgb[i];
    inputs.emplace_back(ToPoint(p), info);
  }
  for (const Eigen::Vector3d& c : cloud.camera_centers_world) lattice.Use(c, 0, &nodes);
  for (std::uint32_t n = 0; n < nodes.size(); ++n) {
    inputs.emplace_back(ToPoint(lattice.Position(nodes[n])), VertexInfo{n, true, false, 0, 0, {}});
  }
  Delaunay dt;
  dt.insert(inputs.begin(), inputs.end());
  SEMAP_ASSERT(dt.dimension() == 3);

  // Vertex of each kept point (duplicates share the vertex that survived).
  std::vector<VertexHandle> vertex_of(cloud.size());
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    if (!v->info().steiner) vertex_of[v->info().id] = v;
  }
  CellHandle hint;
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    if (!kept[i] || vertex_of[i] != VertexHandle()) continue;
    Delaunay::Locate_type lt;
    int li, lj;
    hint = dt.locate(ToPoint(cloud.positions_world[i]), lt, li, lj, hint);
    SEMAP_ASSERT(lt == Delaunay::VERTEX, "a kept point has no vertex");
    vertex_of[i] = hint->vertex(li);
  }

  // Votes.
  const RayGeometry geometry(options);
  RayVotes votes;
  auto trace = [&](std::uint32_t point, std::uint32_t camera) {
    if (!kept[point]) return;
    if (!ComputeRayVotes(dt, vertex_of[point], cloud.camera_centers_world[camera], geometry, &votes)) return;
    ++result.statistics.rays_traced;
    result.statistics.cells_visited += votes.entries.size();
    for (const RayVotes::Entry& e : votes.entries) {
      (e.matter ? e.cell->info().matter_q : e.cell->info().free_q) += e.weight_q;
    }
  };
  for (std::uint32_t i = 0; i < cloud.size(); ++i) trace(i, cloud.camera_index[i]);
  for (const Observation& o : extra_observations) {
    SEMAP_ASSERT(o.point < cloud.size() && o.camera < cloud.camera_centers_world.size(), "bad observation");
    trace(o.point, o.camera);
  }

  // The manifold free-space region.
  ManifoldCarver carver(&dt, options.grow_passes, options.repair_fill_cost_q());
  if (options.extraction == SurfaceExtraction::kGreedyGrowth) {
    // Region growing from the cell with the highest free vote.
    CellHandle seed;
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
      if (c->info().IsFree() && (seed == CellHandle() || c->info().free_q > seed->info().free_q)) seed = c;
    }
    if (seed != CellHandle()) carver.Grow({seed});
  } else {
    std::vector<CellHandle> free_cells, changed;
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
      if (c->info().IsFree()) free_cells.push_back(c);
    }
    carver.CarveAndRepair(free_cells, &changed);
  }

  const Label unlabelled = 0;
  // Ray votes: nothing marks the facets views saw, so none is left out for that.
  const EmitRule emit{options.drop_steiner_triangles, /*drop_unseen=*/false};
  result.mesh = ExtractSurfaceMesh(dt, emit, /*irregular=*/{}, /*frozen=*/nullptr, unlabelled).mesh;
  if (with_cell_votes) result.cell_votes = CollectCellVotes(dt);

  MapStatistics& s = result.statistics;
  s.num_steiner_vertices = nodes.size();
  s.num_points = dt.number_of_vertices() - nodes.size();
  s.num_cells = dt.number_of_finite_cells();
  s.num_carved_cells = CountCarvedCells(dt);
  s.num_free_cells = CountFreeCells(dt);
  s.num_rays = s.rays_traced;
  return result;
}

}  // namespace semap
