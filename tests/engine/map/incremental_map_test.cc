#include "engine/map/incremental_map.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <random>
#include <set>

#include "engine/core/depth_view.h"
#include "engine/core/mesh_delta.h"
#include "engine/map/batch_map.h"
#include "tests/engine/map/manifold_checker.h"
#include "tests/engine/map/map_test_util.h"
#include "tests/engine/map/street_scene.h"

namespace semap {
namespace {

using VoteKey = std::array<double, 12>;

// The exact ray map (these streams have no depth maps, and some tests add extra rays or compare with the
// batch map, which only the ray map has).
MapOptions RayOptions() {
  MapOptions options;
  options.visibility = Visibility::kRays;
  return options;
}

VoteKey KeyOf(const std::array<Eigen::Vector3d, 4>& v) {
  VoteKey k;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) k[3 * i + j] = v[i][j];
  return k;
}

std::map<VoteKey, std::pair<std::int64_t, std::int64_t>> VoteMap(const std::vector<CellVotes>& votes) {
  std::map<VoteKey, std::pair<std::int64_t, std::int64_t>> m;
  for (const auto& c : votes) m[KeyOf(c.vertices)] = {c.free_fixed, c.matter_fixed};
  return m;
}

// Triangles as sets of vertex positions (to compare meshes with different vertex numbering).
std::set<std::array<double, 9>> TriangleSet(const Mesh& mesh) {
  std::set<std::array<double, 9>> s;
  for (const auto& t : mesh.triangles) {
    std::array<Eigen::Vector3d, 3> v{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    std::sort(v.begin(), v.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    std::array<double, 9> k;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) k[3 * i + j] = v[i][j];
    s.insert(k);
  }
  return s;
}

// Triangles by their corners' positions as TriangleSet, but oriented (each in the least of its three
// rotations) and counted: a triangle given twice, or turned over, does not compare equal.
std::multiset<std::array<double, 9>> OrientedTriangles(const Mesh& mesh) {
  std::multiset<std::array<double, 9>> out;
  for (const auto& t : mesh.triangles) {
    std::array<double, 9> key;
    for (int first = 0; first < 3; ++first) {
      std::array<double, 9> rotated;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d& p = mesh.vertices[t[(first + k) % 3]];
        for (int d = 0; d < 3; ++d) rotated[3 * k + d] = p[d];
      }
      if (first == 0 || rotated < key) key = rotated;
    }
    out.insert(key);
  }
  return out;
}

// One frame of a random stream: a camera moving along +y, points scattered on a noisy "street" (ground and
// two walls) ahead of it, some of them re-observations of earlier points (merged by distance) and some extra
// rays to existing point ids.
struct RandomStream {
  explicit RandomStream(unsigned seed) : rng(seed) {}
  std::mt19937 rng;
  std::vector<std::uint32_t> known_ids;

  LabelledCloud Frame(int f, int n, std::vector<Observation>* extra) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.02);
    LabelledCloud cloud;
    const Eigen::Vector3d camera(0.3 * std::sin(f), 1.2 * f, 1.5 + 0.1 * u(rng));
    cloud.camera_centers_world.push_back(camera);
    for (int i = 0; i < n; ++i) {
      const double y = camera.y() + 2.0 + 10.0 * u(rng);
      const int surface = int(3 * u(rng));
      Eigen::Vector3d p;
      if (surface == 0)
        p = {-5.0 + 10.0 * u(rng), y, 0.0};
      else
        p = {surface == 1 ? -5.0 : 5.0, y, 6.0 * u(rng)};
      p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      cloud.positions_world.push_back(p);
      cloud.camera_index.push_back(0);
      cloud.labels.push_back(Label(surface + 1));
    }
    // A few re-observations placed exactly near earlier points are produced by the merge distance; extra
    // rays:
    for (int k = 0; k < 5 && !known_ids.empty(); ++k) {
      extra->push_back({known_ids[std::size_t(u(rng) * known_ids.size()) % known_ids.size()], 0});
    }
    return cloud;
  }
};

void ExpectVotesEqualBatch(const IncrementalMap& map, const MapOptions& options, int* mesh_diff,
                           int* mesh_size) {
  const MapSnapshot snapshot = map.ExportSnapshot();
  const BatchMapResult batch =
      BuildBatchMap(options, snapshot.cloud, snapshot.extra, /*with_cell_votes=*/true);
  const auto incremental_votes = VoteMap(map.CellVotesSnapshot());
  const auto batch_votes = VoteMap(batch.cell_votes);
  ASSERT_EQ(incremental_votes.size(), batch_votes.size()) << "different triangulations";
  std::size_t differing = 0;
  for (const auto& [key, votes] : batch_votes) {
    auto it = incremental_votes.find(key);
    ASSERT_NE(it, incremental_votes.end()) << "a batch cell is missing from the incremental map";
    differing += it->second != votes ? 1 : 0;
  }
  EXPECT_EQ(differing, 0u) << "cells whose votes differ from the batch map";
  // Mesh difference (the repairs and growth run from different states): symmetric difference of triangle
  // sets.
  const auto a = TriangleSet(map.ExtractMesh()), b = TriangleSet(batch.mesh);
  std::vector<std::array<double, 9>> diff;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(diff));
  *mesh_diff = int(diff.size());
  // Measured: 0-24 % of the batch triangles on these streams (see the printed lines); the incremental map
  // keeps its carved cells outside the changed region where the batch map carves and repairs everything.
  EXPECT_LE(double(diff.size()), 0.3 * double(b.size())) << "incremental mesh too far from the batch mesh";
  *mesh_size = int(b.size());
}

TEST(IncrementalMap, VotesEqualBatchOnRandomStreams) {
  MapOptions options = RayOptions();
  options.drop_steiner_triangles = false;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    IncrementalMap map(options);
    RandomStream stream(seed);
    for (int f = 0; f < 6; ++f) {
      std::vector<Observation> extra;
      const LabelledCloud frame = stream.Frame(f, 400, &extra);
      const MapUpdateResult r = map.Update(frame, extra);
      for (std::uint32_t id : r.point_ids) {
        if (id != kDroppedPoint) stream.known_ids.push_back(id);
      }
      const auto report = test::CheckManifold(map.ExtractMesh(), /*allow_boundary=*/false);
      ASSERT_TRUE(report.ok()) << "seed " << seed << " frame " << f << "\n" << report.Summary();
      int diff = 0, size = 0;
      ExpectVotesEqualBatch(map, options, &diff, &size);
      if (HasFatalFailure()) return;
      std::cout << "seed " << seed << " frame " << f << ": inserted " << r.inserted << " merged " << r.merged
                << " retraced " << r.rays_retraced << " destroyed " << r.cells_destroyed << " uncarved "
                << r.cells_uncarved << " carved " << r.cells_carved << "; mesh differs from batch in " << diff
                << " of " << size << " triangles\n";
    }
  }
}

// Mesh vertices carry the label of the point they are (the first observation's label, kept on merges), and
// the cheap per-frame sizes equal the full statistics.
TEST(IncrementalMap, MeshVerticesCarryTheirPointsLabelsAndSizesMatchStatistics) {
  MapOptions options = RayOptions();
  IncrementalMap map(options);
  RandomStream stream(5);
  std::map<std::uint32_t, Label> label_of;
  for (int f = 0; f < 4; ++f) {
    std::vector<Observation> extra;
    const LabelledCloud frame = stream.Frame(f, 300, &extra);
    const MapUpdateResult r = map.Update(frame, extra);
    for (std::size_t i = 0; i < r.point_ids.size(); ++i) {
      if (r.point_ids[i] != kDroppedPoint) label_of.try_emplace(r.point_ids[i], frame.labels[i]);
    }
    const IdentifiedMesh mesh = map.ExtractIdentifiedMesh();
    ASSERT_GT(mesh.mesh.num_triangles(), 0u);
    for (std::size_t v = 0; v < mesh.vertex_ids.size(); ++v) {
      ASSERT_TRUE(label_of.count(std::uint32_t(mesh.vertex_ids[v]))) << "a mesh vertex that is no point";
      EXPECT_EQ(mesh.mesh.labels[v], label_of.at(std::uint32_t(mesh.vertex_ids[v])));
    }
    const MapStatistics full = map.Statistics(), sizes = map.Sizes();
    EXPECT_GT(full.num_carved_cells, 0u);
    EXPECT_EQ(sizes.num_carved_cells, 0u);
    EXPECT_EQ(sizes.num_points, full.num_points);
    EXPECT_EQ(sizes.num_steiner_vertices, full.num_steiner_vertices);
    EXPECT_EQ(sizes.num_cells, full.num_cells);
    EXPECT_EQ(sizes.num_rays, full.num_rays);
    EXPECT_EQ(sizes.rays_traced, full.rays_traced);
  }
}

TEST(IncrementalMap, MergesNearbyPointsAndRejectsUnknownIds) {
  MapOptions options = RayOptions();
  options.merge_distance_m = 0.1;
  IncrementalMap map(options);
  LabelledCloud a;
  a.camera_centers_world = {{0, 0, 0}};
  a.positions_world = {{0, 5, 0}, {1, 5, 0}, {0, 5, 1}, {1, 5, 1}, {0.5, 6, 0.5}, {0.02, 5.0, 0.03}};
  a.camera_index.assign(a.size(), 0);
  const MapUpdateResult r = map.Update(a);
  EXPECT_EQ(r.inserted, 5u);
  EXPECT_EQ(r.merged, 1u);
  EXPECT_EQ(r.point_ids[5], r.point_ids[0]);
  LabelledCloud b = a;
  b.camera_centers_world = {{0.5, 0, 0.2}};
  b.positions_world = {{1.03, 5.0, 0.0}};
  b.camera_index = {0};
  const MapUpdateResult r2 = map.Update(b, {{r.point_ids[4], 0}});
  EXPECT_EQ(r2.merged, 1u);
  EXPECT_EQ(r2.point_ids[0], r.point_ids[1]);
  EXPECT_EQ(map.Statistics().num_rays, 8u);  // 6 + a merged ray + an extra ray
  EXPECT_THROW(map.Update(b, {{12345, 0}}), std::invalid_argument);
}

// The live mesh and the finalised pieces, streamed through core's MeshDiffer, rebuild the published mesh.
TEST(IncrementalMap, DeltasReproduceTheMesh) {
  MapOptions options = RayOptions();
  options.finalise_age_frames = 3;
  options.finalise_every_frames = 1;
  IncrementalMap map(options);
  RandomStream stream(7);
  MeshDiffer differ;
  MeshAccumulator accumulator;
  std::size_t finalised = 0;
  for (int f = 0; f < 7; ++f) {
    std::vector<Observation> extra;
    map.Update(stream.Frame(f, 300, &extra));
    const IdentifiedMesh frozen = map.TakeFinalisedMesh();
    ASSERT_EQ(frozen.vertex_ids.size(), frozen.mesh.num_vertices());
    finalised += frozen.mesh.num_triangles();
    const IdentifiedMesh live = map.ExtractIdentifiedMesh();
    ASSERT_EQ(live.vertex_ids.size(), live.mesh.num_vertices());
    accumulator.Apply(differ.Update(f, live, frozen));
    EXPECT_EQ(accumulator.num_triangles(), live.mesh.num_triangles() + finalised) << "frame " << f;
  }
  EXPECT_GT(finalised, 100u);
}

// What a subscriber sees: the finalised pieces and the live mesh, streamed through core's MeshDiffer and
// rebuilt by a MeshAccumulator.
struct PublishedMesh {
  MeshDiffer differ;
  MeshAccumulator accumulator;
  // Takes the map's finalised triangles and live mesh after an update; returns the finalised ones.
  Mesh Update(IncrementalMap* map, int frame) {
    const IdentifiedMesh frozen = map->TakeFinalisedMesh();
    accumulator.Apply(differ.Update(frame, map->ExtractIdentifiedMesh(), frozen));
    return frozen.mesh;
  }
};

TEST(IncrementalMap, MemoryStaysBoundedOnALongDrive) {
  MapOptions options = RayOptions();
  options.finalise_age_frames = 8;
  options.finalise_every_frames = 4;
  // The whole surface (Steiner triangles kept) is a closed 2-manifold: the finalised pieces and the live
  // surface together, across every seam of finalisation.
  options.drop_steiner_triangles = false;
  IncrementalMap map(options);
  RandomStream stream(11);
  PublishedMesh published;
  std::size_t max_early = 0, max_late = 0, finalised_triangles = 0;
  std::set<std::array<double, 9>> finalised;
  const int frames = 60;
  for (int f = 0; f < frames; ++f) {
    std::vector<Observation> extra;
    stream.known_ids.clear();  // extra rays only to live points: keep none (old ids may be finalised)
    map.Update(stream.Frame(f, 200, &extra));
    const MapStatistics s = map.Statistics();
    if (f >= 15 && f < 30) max_early = std::max(max_early, s.num_cells);
    if (f >= frames - 15) max_late = std::max(max_late, s.num_cells);
    const Mesh m = published.Update(&map, f);
    finalised_triangles += m.num_triangles();
    for (const auto& key : TriangleSet(m)) EXPECT_TRUE(finalised.insert(key).second) << "finalised twice";
    const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/false);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  const MapStatistics s = map.Statistics();
  std::cout << "live points " << s.num_points << ", cells " << s.num_cells
            << " (max frames 15-30: " << max_early << ", last 15: " << max_late << "), finalised triangles "
            << finalised_triangles << "\n";
  EXPECT_LE(s.num_points, 200u * 13);  // at most the last 8 + 4 + 1 frames live
  EXPECT_LT(double(max_late), 1.3 * double(max_early));
  EXPECT_GT(finalised_triangles, 1000u);
}

// With the Steiner triangles left out (the default) the published mesh has a boundary, and the vertices
// where left-out triangles cut a fan in several pieces get one copy per piece: after every frame of a drive
// that finalises often, the published mesh (finalised pieces and live surface: the live surface alone is open
// along the seams, and may pinch there) has every edge in one or two triangles, every vertex a single fan,
// orientations agree and no triangle is degenerate or repeated.
TEST(IncrementalMap, PublishedMeshIsManifoldAcrossFinalisationSeams) {
  for (const int every : {1, 3}) {
    MapOptions options = RayOptions();
    options.finalise_age_frames = 5;
    options.finalise_every_frames = every;
    IncrementalMap map(options);
    RandomStream stream(13 + unsigned(every));
    PublishedMesh published;
    std::size_t finalised_triangles = 0, split = 0;
    for (int f = 0; f < 40; ++f) {
      std::vector<Observation> extra;
      stream.known_ids.clear();
      map.Update(stream.Frame(f, 250, &extra));
      finalised_triangles += published.Update(&map, f).num_triangles();
      const IdentifiedMesh live = map.ExtractIdentifiedMesh();
      for (VertexId id : live.vertex_ids) split += (id >> 32) & 0xFF ? 1 : 0;
      const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/true);
      ASSERT_TRUE(report.ok()) << "published mesh, every " << every << ", frame " << f << "\n"
                               << report.Summary();
    }
    std::cout << "finalise every " << every << ": " << finalised_triangles << " finalised triangles, "
              << split << " vertex copies seen in the live meshes\n";
    EXPECT_GT(finalised_triangles, 1000u);
  }
}

// A drive that jumps onto new ground (as a looped soak does) after its old part was finalised: the new points
// lie outside the convex hull, whose vertices are partly frozen seams; they are still inserted (the soak
// once lost every point there, and finalisation then emptied the map), and the published mesh stays manifold.
TEST(IncrementalMap, DriveJumpingPastTheHullKeepsMapping) {
  MapOptions options = RayOptions();
  options.finalise_age_frames = 3;
  options.finalise_every_frames = 2;
  IncrementalMap map(options);
  RandomStream stream(21);
  PublishedMesh published;
  for (int f = 0; f < 24; ++f) {
    std::vector<Observation> extra;
    stream.known_ids.clear();
    const int place = f < 12 ? f : f + 120;  // 120 frames further on (144 m) from frame 12
    const MapUpdateResult r = map.Update(stream.Frame(place, 200, &extra));
    if (f >= 12) {
      EXPECT_GT(r.inserted, 100u) << "frame " << f << ": " << r.points_rejected_at_seam << " rejected";
    }
    published.Update(&map, f);
    const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  EXPECT_GT(map.Statistics().num_points, 200u);
}

// Cells by the 1 m voxels their bounding boxes touch, to find the cell holding a point.
class CellLocator {
 public:
  explicit CellLocator(std::vector<CellVotes> cells) : cells_(std::move(cells)) {
    for (std::size_t i = 0; i < cells_.size(); ++i) {
      Eigen::Vector3d lo = cells_[i].vertices[0], hi = lo;
      for (const auto& v : cells_[i].vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      if ((hi - lo).maxCoeff() > 40.0) continue;  // Steiner-sized cells: outside the sampled box anyway
      for (int x = int(std::floor(lo.x())); x <= int(std::floor(hi.x())); ++x)
        for (int y = int(std::floor(lo.y())); y <= int(std::floor(hi.y())); ++y)
          for (int z = int(std::floor(lo.z())); z <= int(std::floor(hi.z())); ++z)
            grid_[{x, y, z}].push_back(i);
    }
  }
  // The cell holding p, or nullptr.
  const CellVotes* Find(const Eigen::Vector3d& p) const {
    const auto it = grid_.find({int(std::floor(p.x())), int(std::floor(p.y())), int(std::floor(p.z()))});
    if (it == grid_.end()) return nullptr;
    for (std::size_t i : it->second) {
      const auto& t = cells_[i].vertices;
      bool inside = true;
      for (int f = 0; f < 4 && inside; ++f) {
        const Eigen::Vector3d& a = t[(f + 1) % 4];
        const Eigen::Vector3d n = (t[(f + 2) % 4] - a).cross(t[(f + 3) % 4] - a);
        inside = n.dot(t[f] - a) * n.dot(p - a) >= 0.0;
      }
      if (inside) return &cells_[i];
    }
    return nullptr;
  }

 private:
  std::vector<CellVotes> cells_;
  std::map<std::array<int, 3>, std::vector<std::size_t>> grid_;
};

// map.visibility: depth on a drive down the analytic street with exact depth maps: the frames' points are
// merged into the vertices they land on, the published mesh stays a 2-manifold across finalisation seams
// after every frame, and it lies on the street about as well as the exact ray map's built from the same
// points (each point a ray).
TEST(IncrementalMap, DepthVotesMapTheStreetAsWellAsTheRays) {
  const test::StreetScene scene;
  const auto distance = [&](const Eigen::Vector3d& p) { return scene.Distance(p); };
  MapOptions options;
  options.finalise_age_frames = 10;
  options.finalise_every_frames = 3;
  options.disparity_sigma_px = 0.0;  // exact depth
  // Like with like: the ray map inserts every point, so the depth map does too (a held far point leaves the
  // cells around it larger, free where the ray map's smaller cells behind the point are matter).
  options.confirm_beyond_m = 0.0;
  // And merges no coarser than these frames' points lie (2 px apart; the default radius, about a stream's
  // point spacing, would leave a fraction of them, in larger cells than the ray map's).
  options.merge_radius_px = 3.0;
  MapOptions rays_options = options;
  rays_options.visibility = Visibility::kRays;
  options.visibility = Visibility::kDepth;
  IncrementalMap depth_map(options), rays_map(rays_options);
  PublishedMesh depth_published, rays_published;
  std::size_t points = 0, inserted = 0;
  for (int f = 0; f < 30; ++f) {
    LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    points += frame.size();
    inserted += depth_map.Update(frame).inserted;
    frame.camera_views.clear();
    rays_map.Update(frame);
    depth_published.Update(&depth_map, f);
    rays_published.Update(&rays_map, f);
    const auto report = test::CheckManifold(depth_published.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  depth_published.accumulator.Apply(
      depth_published.differ.Update(30, depth_map.ExtractIdentifiedMesh(), depth_map.TakeFinalisedMesh()));
  const Mesh depth_mesh = depth_published.accumulator.ToMesh();
  const Mesh rays_mesh = rays_published.accumulator.ToMesh();
  const test::SurfaceError depth_error = test::MeshError(depth_mesh, distance);
  const test::SurfaceError rays_error = test::MeshError(rays_mesh, distance);
  std::cout << "depth votes: " << inserted << " of " << points << " points inserted, "
            << depth_mesh.num_triangles() << " triangles, median " << depth_error.median_m << " m, RMSE "
            << depth_error.rmse_m << " m; rays: " << rays_mesh.num_triangles() << " triangles, median "
            << rays_error.median_m << " m, RMSE " << rays_error.rmse_m << " m\n";
  // Free / matter agreement with the exact ray votes by volume, over the street the live window sees
  // (uniform samples; a sample counts where both maps have a live cell holding it).
  {
    const CellLocator depth_cells(depth_map.CellVotesSnapshot()), rays_cells(rays_map.CellVotesSnapshot());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> x(-7.0, 7.0), y(22.0, 50.0), z(-0.5, 8.5);
    int both = 0, agree = 0, table[2][2][2] = {},
        unvoted = 0;  // [depth free][rays free][inside the scene's surfaces]
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector3d p(x(rng), y(rng), z(rng));
      const CellVotes *a = depth_cells.Find(p), *b = rays_cells.Find(p);
      if (!a || !b || a->sealed || b->sealed) continue;  // released space: no votes kept
      ++both;
      const bool depth_free = a->free_fixed > a->matter_fixed, rays_free = b->free_fixed > b->matter_fixed;
      const bool open = std::abs(p.x()) < scene.half_width_m && p.z() > 0.0;
      ++table[depth_free][rays_free][open];
      unvoted += a->free_fixed == 0 && a->matter_fixed == 0 ? 1 : 0;
      agree += depth_free == rays_free ? 1 : 0;
    }
    std::cout << "free/matter agreement with the ray votes by volume: " << 100.0 * agree / both << " % of "
              << both << " samples (depth/rays free, in the street: ff " << table[1][1][1] << " fm "
              << table[1][0][1] << " mf " << table[0][1][1] << " mm " << table[0][0][1] << "; outside: ff "
              << table[1][1][0] << " fm " << table[1][0][0] << " mf " << table[0][1][0] << " mm "
              << table[0][0][0] << "), depth cells without votes " << unvoted << "\n";
    EXPECT_GT(both, 3000);
    // Measured 95.8 % (against an aim of 97 %). Most of the disagreement is where the reference is wrong:
    // cells in the street's air (truly free) that the depth map votes free and the rays leave matter (their
    // matter extension behind the points, their smaller cells along the walls and the ground).
    EXPECT_GT(double(agree) / both, 0.93);
    // So each map is also held against the scene itself: free in the street's air, not free behind its
    // surfaces. Measured: depth votes 96.1 %, ray votes 95.2 % of the samples.
    const int depth_right = table[1][1][1] + table[1][0][1] + table[0][0][0] + table[0][1][0];
    const int rays_right = table[1][1][1] + table[0][1][1] + table[0][0][0] + table[1][0][0];
    std::cout << "free where the street is open, matter behind its surfaces: depth votes "
              << 100.0 * depth_right / both << " %, ray votes " << 100.0 * rays_right / both << " %\n";
    EXPECT_GE(depth_right, rays_right)
        << "the depth votes are at least as true to the scene as the ray votes";
  }
  EXPECT_LT(double(inserted), 0.5 * double(points)) << "re-observed points should merge";
  EXPECT_GT(depth_mesh.num_triangles(), 1000u);
  EXPECT_LT(depth_error.median_m, 0.05);
  EXPECT_LT(depth_error.rmse_m, 1.05 * rays_error.rmse_m + 0.02);
}

// Share of `mesh`'s area farther than `far_m` from the street, by area: each triangle split 4 times (16
// pieces), each piece's centroid standing for its area.
double AreaShareBeyond(const Mesh& mesh, const test::StreetScene& scene, double far_m) {
  double total = 0.0, beyond = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    constexpr int kSplit = 4;
    for (int i = 0; i < kSplit; ++i) {
      for (int j = 0; i + j < kSplit; ++j) {
        // The upright piece at (i, j) and, where there is one, the inverted piece beside it.
        for (int flip = 0; flip < (i + j + 1 < kSplit ? 2 : 1); ++flip) {
          const double u = (i + (flip ? 2.0 : 1.0) / 3.0) / kSplit,
                       v = (j + (flip ? 2.0 : 1.0) / 3.0) / kSplit;
          const Eigen::Vector3d p = a + u * (b - a) + v * (c - a);
          const double piece = area / (kSplit * kSplit);
          total += piece;
          if (scene.Distance(p) > far_m) beyond += piece;
        }
      }
    }
  }
  return total > 0.0 ? beyond / total : 0.0;
}

// map.drop_unseen_surface: the camera sees the street's walls up to a few metres and the sky above them; the
// carved region still meets unseen space (above the field of view near the camera, behind the walls' tops).
// The facets there are left out, so little of the mesh lies off the street; what a view saw stays (the
// triangles near the street are nearly the same), and the mesh stays a 2-manifold after every frame.
TEST(IncrementalMap, DepthVotesEmitOnlyTheSurfaceSomeViewSaw) {
  const test::StreetScene scene;
  MapOptions options;
  options.finalise_age_frames = 10;
  options.finalise_every_frames = 3;
  options.disparity_sigma_px = 0.0;  // exact depth
  options.visibility = Visibility::kDepth;
  MapOptions keep_options = options;
  keep_options.drop_unseen_surface = false;
  IncrementalMap map(options), keep_map(keep_options);
  PublishedMesh published, keep_published;
  for (int f = 0; f < 30; ++f) {
    const LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    map.Update(frame);
    keep_map.Update(frame);
    published.Update(&map, f);
    keep_published.Update(&keep_map, f);
    const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  const Mesh mesh = published.accumulator.ToMesh(), kept = keep_published.accumulator.ToMesh();
  constexpr double kFarM = 0.5;
  const double beyond = AreaShareBeyond(mesh, scene, kFarM),
               kept_beyond = AreaShareBeyond(kept, scene, kFarM);
  std::cout << "area beyond " << kFarM << " m: " << 100.0 * beyond << " % of " << mesh.num_triangles()
            << " triangles (all surface facets: " << 100.0 * kept_beyond << " % of " << kept.num_triangles()
            << ")\n";
  EXPECT_LT(beyond, 0.25 * kept_beyond);  // measured 0.75 % against 5.7 %
  EXPECT_LT(beyond, 0.02);
  // What lies on the street is kept: the area within 0.1 m of it loses little (measured 3 %).
  const auto near_street = [&](const Mesh& m) {
    double area = 0.0;
    for (const auto& t : m.triangles) {
      const Eigen::Vector3d &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      if (scene.Distance((a + b + c) / 3.0) < 0.1) area += 0.5 * (b - a).cross(c - a).norm();
    }
    return area;
  };
  std::cout << "area near the street " << near_street(mesh) << " m2 (all: " << near_street(kept) << " m2)\n";
  EXPECT_GT(near_street(mesh), 0.9 * near_street(kept));
}

// Vertices noisier than what the views see (exact depth maps, points moved by 0.15 m): facets tilted by their
// vertices' noise miss the seen tolerance (0.1 m) among facets that pass, and leave holes in the street.
// map.fill_unseen_holes_facets fills those of one facet: the published mesh stays a 2-manifold after every
// frame, the surface that either map emits is the same carving, and the filled one has fewer open edges.
TEST(IncrementalMap, DepthVotesFillOneFacetHolesInTheSeenSurface) {
  const test::StreetScene scene;
  MapOptions options;
  options.finalise_age_frames = 10;
  options.finalise_every_frames = 3;
  options.disparity_sigma_px = 0.0;  // the tolerance is the ray extension alone
  options.visibility = Visibility::kDepth;
  options.fill_unseen_holes_facets = 1;
  MapOptions holes_options = options;
  holes_options.fill_unseen_holes_facets = 0;
  IncrementalMap map(options), holes_map(holes_options);
  PublishedMesh published, holes_published;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise_m(0.0, 0.15);
  for (int f = 0; f < 30; ++f) {
    LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    for (Eigen::Vector3d& p : frame.positions_world)
      p += Eigen::Vector3d(noise_m(rng), noise_m(rng), noise_m(rng));
    map.Update(frame);
    holes_map.Update(frame);
    published.Update(&map, f);
    holes_published.Update(&holes_map, f);
    const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  EXPECT_GT(map.Statistics().facets_taken_as_seen, 0u);
  EXPECT_EQ(holes_map.Statistics().facets_taken_as_seen, 0u);
  EXPECT_EQ(map.Statistics().num_carved_cells, holes_map.Statistics().num_carved_cells)
      << "seen bits change what is emitted, never the carving";
  const Mesh filled = published.accumulator.ToMesh(), holed = holes_published.accumulator.ToMesh();
  const auto filled_report = test::CheckManifold(filled, true),
             holed_report = test::CheckManifold(holed, true);
  std::cout << "triangles " << filled.num_triangles() << " (no filling: " << holed.num_triangles()
            << "), open edges " << filled_report.num_boundary_edges << " (" << holed_report.num_boundary_edges
            << ")\n";
  EXPECT_GT(filled.num_triangles(), holed.num_triangles());
  EXPECT_LT(filled_report.num_boundary_edges, holed_report.num_boundary_edges);
}

// Moves each point of a street frame (camera looking along +y) along its ray by k·z² times a draw of `unit`,
// stereo-like depth noise; returns the points' exact depths z.
std::vector<double> AddDepthSquaredNoise(double k, LabelledCloud* frame,
                                         std::normal_distribution<double>* unit, std::mt19937* rng) {
  const Eigen::Vector3d camera = frame->camera_centers_world[0];
  std::vector<double> depths;
  for (Eigen::Vector3d& p : frame->positions_world) {
    const double z = (p - camera).y();
    depths.push_back(z);
    p += (p - camera).normalized() * (k * z * z * (*unit)(*rng));
  }
  return depths;
}

// map.confirm_beyond_m: the same street with σ_z = k·z² noise. Points beyond 10 m wait for a later frame's
// point to land on them (the first frame's are held: no id, nothing live beyond 10 m); the confirmed pairs
// become vertices at their 1/z⁴-weighted mean. The published mesh stays a 2-manifold after every frame and
// its vertices lie nearer the street than when every point is inserted at once.
TEST(IncrementalMap, DepthVotesConfirmFarPointsBeforeInsertingThem) {
  const test::StreetScene scene;
  constexpr double kNoisePerDepth2 = 0.001;  // σ_z = 0.1 m at 10 m, 0.4 m at 20 m
  constexpr double kConfirmBeyondM = 10.0;
  MapOptions options;
  options.finalise_age_frames = 10;
  options.finalise_every_frames = 3;
  options.visibility = Visibility::kDepth;
  options.fuse_gate_sigmas = 0.0;  // the rule on first-sighting vertices
  MapOptions plain_options = options;
  plain_options.confirm_beyond_m = 0.0;
  options.confirm_beyond_m = kConfirmBeyondM;
  IncrementalMap map(options), plain_map(plain_options);
  PublishedMesh published, plain_published;
  std::mt19937 rng(13);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::size_t held = 0, confirmed = 0;
  for (int f = 0; f < 30; ++f) {
    LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    const Eigen::Vector3d camera = frame.camera_centers_world[0];
    const std::vector<double> depths = AddDepthSquaredNoise(kNoisePerDepth2, &frame, &unit, &rng);
    const MapUpdateResult r = map.Update(frame);
    const MapUpdateResult plain = plain_map.Update(frame);
    EXPECT_EQ(plain.points_held + plain.points_confirmed, 0u);
    held += r.points_held;
    confirmed += r.points_confirmed;
    if (f == 0) {
      // Nothing to confirm against yet: every far point is held, every near one is a vertex.
      std::size_t far = 0;
      for (std::size_t i = 0; i < depths.size(); ++i) {
        if (depths[i] > kConfirmBeyondM + 0.5) {  // the noise moves points across the threshold a little
          ++far;
          EXPECT_EQ(r.point_ids[i], kDroppedPoint);
        } else if (depths[i] < kConfirmBeyondM - 0.5) {
          EXPECT_NE(r.point_ids[i], kDroppedPoint);
        }
      }
      EXPECT_GT(far, 100u);
      EXPECT_EQ(r.points_confirmed, 0u);
    }
    published.Update(&map, f);
    plain_published.Update(&plain_map, f);
    if (f == 0) {
      const Mesh first = published.accumulator.ToMesh();
      EXPECT_GT(first.num_triangles(), 0u);
      for (const auto& p : first.vertices) EXPECT_LE((p - camera).y(), kConfirmBeyondM + 1.0);
    }
    const auto report = test::CheckManifold(published.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
  }
  const auto distance = [&](const Eigen::Vector3d& p) { return scene.Distance(p); };
  const Mesh mesh = published.accumulator.ToMesh(), plain = plain_published.accumulator.ToMesh();
  const test::SurfaceError error = test::MeshError(mesh, distance),
                           plain_error = test::MeshError(plain, distance);
  std::cout << held << " far points held, " << confirmed << " confirmed; " << mesh.num_triangles()
            << " triangles, median " << error.median_m << " m, mean " << error.mean_m
            << " m (every point at once: " << plain.num_triangles() << " triangles, median "
            << plain_error.median_m << " m, mean " << plain_error.mean_m << " m)\n";
  EXPECT_GT(confirmed, 100u);
  EXPECT_GT(mesh.num_triangles(), 1000u);
  EXPECT_LT(error.mean_m, plain_error.mean_m);
}

// The end of a stream: the far points still held become vertices where their one sighting put them
// (IncrementalMap::InsertHeldPoints). A one-frame map of the exact street gets its far surface; the mesh
// stays a 2-manifold on the street, and a second call has nothing left to insert.
TEST(IncrementalMap, HeldFarPointsJoinTheMapAtTheEndOfTheStream) {
  const test::StreetScene scene;
  constexpr double kConfirmBeyondM = 10.0;
  MapOptions options;
  options.visibility = Visibility::kDepth;
  options.confirm_beyond_m = kConfirmBeyondM;
  IncrementalMap map(options);
  const LabelledCloud frame = test::StreetDepthFrame(scene, 0.0, 2);
  const Eigen::Vector3d camera = frame.camera_centers_world[0];
  const MapUpdateResult first = map.Update(frame);
  ASSERT_GT(first.points_held, 100u);
  const auto farthest = [&](const Mesh& mesh) {
    double farthest_m = 0.0;
    for (const auto& p : mesh.vertices) farthest_m = std::max(farthest_m, (p - camera).y());
    return farthest_m;
  };
  const Mesh before = map.ExtractMesh();
  EXPECT_LE(farthest(before), kConfirmBeyondM + 1.0);

  const MapUpdateResult end = map.InsertHeldPoints();
  EXPECT_EQ(end.points_held_inserted, first.points_held);
  const Mesh after = map.ExtractMesh();
  std::cout << first.points_held << " held points inserted: " << before.num_triangles() << " → "
            << after.num_triangles() << " triangles, farthest vertex " << farthest(before) << " → "
            << farthest(after) << " m ahead\n";
  EXPECT_GT(after.num_triangles(), before.num_triangles() + 100);
  EXPECT_GT(farthest(after), kConfirmBeyondM + 5.0);
  double worst_m = 0.0;
  for (const auto& p : after.vertices) worst_m = std::max(worst_m, scene.Distance(p));
  EXPECT_LT(worst_m, 1e-6) << "a vertex off the street (each is a point of the exact frame)";
  const auto report = test::CheckManifold(after, /*allow_boundary=*/true);
  EXPECT_TRUE(report.ok()) << report.Summary();

  EXPECT_EQ(map.InsertHeldPoints().points_held_inserted, 0u);
  EXPECT_EQ(map.ExtractMesh().num_triangles(), after.num_triangles());
}

TEST(IncrementalMap, DepthVotesNeedADepthViewPerCamera) {
  MapOptions options;
  options.visibility = Visibility::kDepth;
  IncrementalMap map(options);
  LabelledCloud frame = test::StreetDepthFrame(test::StreetScene(), 0.0, 4);
  frame.camera_views.clear();
  EXPECT_THROW(map.Update(frame), std::invalid_argument);
}

}  // namespace
}  // namespace semap

namespace semap {
namespace {

// Sizes() counts the finite cells without walking them: the same count as the cells the votes snapshot lists.
TEST(IncrementalMap, SizesCountsEveryFiniteCell) {
  const test::StreetScene scene;
  MapOptions options;
  options.finalise_age_frames = 4;
  options.finalise_every_frames = 2;
  IncrementalMap map(options);
  EXPECT_EQ(map.Sizes().num_cells, 0u);
  for (int f = 0; f < 8; ++f) {
    map.Update(test::StreetDepthFrame(scene, 1.0 * f, 4));
    EXPECT_EQ(map.Sizes().num_cells, map.CellVotesSnapshot().size()) << "frame " << f;
  }
}

namespace fusion_test {

constexpr double kFocalBaselineMPx = 24.0;  // StreetDepthFrame's f·B (48 px × 0.5 m)
constexpr double kDisparitySigmaPx = 0.06;  // the noisy street's: σ_z = D² · 0.06 / 24 = 0.0025 D²

// The street frame at y_m with stereo-like noise on its depth view: each pixel's depth D becomes
// D + σ_z·n, σ_z = D²·disparity_sigma_px/(f·B), n a standard normal draw; the frame's points move with their
// pixels' depths (they are the view's points, as the depth stage makes them).
LabelledCloud NoisyStreetFrame(const test::StreetScene& scene, double y_m, double disparity_sigma_px,
                               std::mt19937* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  LabelledCloud frame = test::StreetDepthFrame(scene, y_m, 2);
  auto view = std::make_shared<DepthView>(*frame.camera_views[0]);
  view->depth_m = view->depth_m.clone();
  cv::Mat& depth = view->depth_m;
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      float& d = depth.at<float>(v, u);
      if (d > 0.0f && d != kFreeToFarRange)
        d += float(d * d * disparity_sigma_px / kFocalBaselineMPx * unit(*rng));
    }
  }
  const Eigen::Vector3d camera = frame.camera_centers_world[0];
  const Pose3d cam_from_world = view->world_from_cam.inverse();
  for (Eigen::Vector3d& p : frame.positions_world) {
    const Eigen::Vector3d p_cam = cam_from_world * p;
    const Eigen::Vector2d uv = view->intrinsics.Project(p_cam);
    const float noisy = depth.at<float>(int(std::lround(uv.y())), int(std::lround(uv.x())));
    p = camera + (p - camera) * (double(noisy) / p_cam.z());
  }
  frame.camera_views[0] = view;
  return frame;
}

// bias_m: the mean error of the rays within kBiasWindowM (a mesh hole seen through is a structural error,
// not a bias; the paper protocol leaves out errors beyond 2 m the same way).
constexpr double kBiasWindowM = 1.0;
struct RayErrors {
  double bias_m = 0.0, rmse_m = 0.0, median_abs_m = 0.0;
  std::size_t rays = 0;
};

double MedianAbs(std::vector<double> errors) {
  if (errors.empty()) return 0.0;
  for (double& e : errors) e = std::abs(e);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

// Per pixel of the frames' views (the cameras at `frames`, at or nearer than max_depth_m of exact depth):
// the mesh's depth and the frame's own noisy depth, each against the exact depth, over the pixels where the
// mesh has a surface.
struct FusionErrors {
  RayErrors mesh, frame;
};
FusionErrors PixelErrors(const Mesh& mesh, const test::StreetScene& scene,
                         const std::vector<LabelledCloud>& frames, double max_depth_m) {
  std::vector<double> mesh_errors, frame_errors;
  for (const LabelledCloud& frame : frames) {
    const DepthView& view = *frame.camera_views[0];
    const LabelledCloud exact = test::StreetDepthFrame(scene, view.world_from_cam.translation().y(), 2);
    const cv::Mat& exact_depth = exact.camera_views[0]->depth_m;
    for (int v = 0; v < exact_depth.rows; ++v) {
      for (int u = 0; u < exact_depth.cols; ++u) {
        const float d = exact_depth.at<float>(v, u);
        if (d <= 0.0f || d == kFreeToFarRange || d > max_depth_m) continue;
        const Eigen::Vector3d ray_cam((u - view.intrinsics.cx_px) / view.intrinsics.fx_px,
                                      (v - view.intrinsics.cy_px) / view.intrinsics.fy_px, 1.0);
        const auto hit = test::RayMeshDistance(mesh, view.world_from_cam.translation(),
                                               view.world_from_cam.linear() * ray_cam.normalized());
        if (!hit) continue;
        mesh_errors.push_back(*hit / ray_cam.norm() - d);
        frame_errors.push_back(view.depth_m.at<float>(v, u) - d);
      }
    }
  }
  const auto figures = [](const std::vector<double>& errors) {
    RayErrors r;
    double sum_sq = 0.0, sum_within = 0.0;
    std::size_t within = 0;
    for (const double e : errors) {
      sum_sq += e * e;
      if (std::abs(e) <= kBiasWindowM) {
        sum_within += e;
        ++within;
      }
    }
    r.rays = errors.size();
    if (!errors.empty()) r.rmse_m = std::sqrt(sum_sq / errors.size());
    if (within > 0) r.bias_m = sum_within / within;
    r.median_abs_m = MedianAbs(errors);
    return r;
  };
  return {figures(mesh_errors), figures(frame_errors)};
}

}  // namespace fusion_test

// Stereo-like noise on every depth map (σ_z = 0.25 m at 10 m, 1 m at 20 m): the votes by each point's own σ
// and the fused vertices put the mesh where the surfaces are (its mean error at the frames' pixels is near
// 0), where the paper's exact-point votes with first-sighting vertices put it behind them; and it is more
// accurate by median and RMSE.
TEST(IncrementalMap, FusedSightingsCentreTheMesh) {
  const test::StreetScene scene;
  using fusion_test::kDisparitySigmaPx;
  constexpr int kFrames = 30;
  MapOptions fused;
  fused.visibility = Visibility::kDepth;
  fused.disparity_sigma_px = kDisparitySigmaPx;  // the map's noise model is the depth maps'
  fused.confirm_beyond_m = 0.0;
  // Vertices follow their estimates closely in the triangulation (the default, 3σ, moves a fifth as many for
  // the map thread's time, and the output follows the estimates from 1σ on: map.fuse_output_sigmas).
  MapOptions by_default = fused;  // the default thresholds, checked below
  fused.fuse_move_sigmas = 1.0;
  // The fused and the exact-point maps at a vertex density near these frames' points (2 px apart); the
  // defaults, at their coarser one (map.merge_radius_px), are checked against exact-point votes at theirs.
  fused.merge_radius_px = 3.0;
  MapOptions paper = fused;
  paper.disparity_sigma_px = 0.0;  // exact-point weights, vertices at their first sighting
  MapOptions paper_by_default = paper;
  paper_by_default.merge_radius_px = by_default.merge_radius_px;
  IncrementalMap fused_map(fused), paper_map(paper), default_map(by_default),
      paper_default_map(paper_by_default);
  PublishedMesh fused_mesh, paper_mesh, default_mesh, paper_default_mesh;
  std::mt19937 rng(21);
  std::vector<LabelledCloud> evaluated;  // every other frame of the first two thirds
  std::size_t moved = 0;
  for (int f = 0; f < kFrames; ++f) {
    const LabelledCloud frame = fusion_test::NoisyStreetFrame(scene, 1.0 * f, kDisparitySigmaPx, &rng);
    moved += fused_map.Update(frame).vertices_moved;
    paper_map.Update(frame);
    default_map.Update(frame);
    paper_default_map.Update(frame);
    fused_mesh.Update(&fused_map, f);
    paper_mesh.Update(&paper_map, f);
    default_mesh.Update(&default_map, f);
    paper_default_mesh.Update(&paper_default_map, f);
    const auto report = test::CheckManifold(fused_mesh.accumulator.ToMesh(), /*allow_boundary=*/true);
    ASSERT_TRUE(report.ok()) << "frame " << f << "\n" << report.Summary();
    if (f % 2 == 0 && f < 2 * kFrames / 3) evaluated.push_back(frame);
  }
  constexpr double kMaxDepthM = 20.0;
  const auto fused_errors =
      fusion_test::PixelErrors(fused_mesh.accumulator.ToMesh(), scene, evaluated, kMaxDepthM);
  const auto paper_errors =
      fusion_test::PixelErrors(paper_mesh.accumulator.ToMesh(), scene, evaluated, kMaxDepthM);
  std::cout << moved << " vertices moved; fused mesh: bias " << fused_errors.mesh.bias_m
            << " m, median |error| " << fused_errors.mesh.median_abs_m << " m, RMSE "
            << fused_errors.mesh.rmse_m << " m over " << fused_errors.mesh.rays
            << " px (the frames there: bias " << fused_errors.frame.bias_m << " m, median "
            << fused_errors.frame.median_abs_m << " m); exact-point votes: bias " << paper_errors.mesh.bias_m
            << " m, median " << paper_errors.mesh.median_abs_m << " m, RMSE " << paper_errors.mesh.rmse_m
            << " m over " << paper_errors.mesh.rays << " px (the frames there: median "
            << paper_errors.frame.median_abs_m << " m)\n";
  // Measured (seed 21): bias 0.030 against 0.083 m, median 0.060 against 0.074 m, RMSE 0.34 against 0.42 m;
  // the frames' own median there is 0.056 m: on this sparse synthetic street the fused mesh is about as
  // accurate as one frame at its pixels, not better (bench/RESULTS.md, "Fusion").
  EXPECT_GT(moved, 100u);
  EXPECT_GT(fused_errors.mesh.rays, paper_errors.mesh.rays);
  EXPECT_GT(paper_errors.mesh.bias_m, 0.06)
      << "exact-point votes on noisy depth: the mesh behind the surfaces";
  EXPECT_LT(std::abs(fused_errors.mesh.bias_m), 0.5 * paper_errors.mesh.bias_m);
  EXPECT_LT(fused_errors.mesh.median_abs_m, 0.9 * paper_errors.mesh.median_abs_m);
  EXPECT_LT(fused_errors.mesh.rmse_m, 0.9 * paper_errors.mesh.rmse_m);
  // With the defaults (moves at 3σ, the output at each vertex's estimate from 1σ on) the mesh is centred too,
  // no less accurate than exact-point votes at the same vertex density, and more accurate by median than the
  // frames themselves at its pixels: the fused sightings beat any one of them.
  const auto default_errors =
      fusion_test::PixelErrors(default_mesh.accumulator.ToMesh(), scene, evaluated, kMaxDepthM);
  const auto paper_default_errors =
      fusion_test::PixelErrors(paper_default_mesh.accumulator.ToMesh(), scene, evaluated, kMaxDepthM);
  std::cout << "defaults: bias " << default_errors.mesh.bias_m << " m, median "
            << default_errors.mesh.median_abs_m << " m, RMSE " << default_errors.mesh.rmse_m
            << " m (the frames there: median " << default_errors.frame.median_abs_m
            << " m); exact-point votes at that density: bias " << paper_default_errors.mesh.bias_m
            << " m, median " << paper_default_errors.mesh.median_abs_m << " m, RMSE "
            << paper_default_errors.mesh.rmse_m << " m\n";
  EXPECT_LT(std::abs(default_errors.mesh.bias_m), 0.5 * paper_default_errors.mesh.bias_m);
  EXPECT_LT(default_errors.mesh.median_abs_m, paper_default_errors.mesh.median_abs_m);
  EXPECT_LT(default_errors.mesh.rmse_m, paper_default_errors.mesh.rmse_m);
  EXPECT_LT(default_errors.mesh.median_abs_m, 0.9 * default_errors.frame.median_abs_m);
}

// The output follows the vertices' fused estimates (map.fuse_output_sigmas) under new output ids: a
// subscriber that applies the deltas holds, triangle for triangle and at the same positions, the finalised
// pieces and the live mesh the map writes, across seams of finalisation; without it the output is at the
// triangulation's positions.
TEST(IncrementalMap, FusedOutputDeltasReproduceTheMesh) {
  const test::StreetScene scene;
  using fusion_test::kDisparitySigmaPx;
  MapOptions options;
  options.visibility = Visibility::kDepth;
  options.disparity_sigma_px = kDisparitySigmaPx;
  options.confirm_beyond_m = 0.0;
  options.finalise_distance_m = 12.0;  // seams of finalisation within the drive
  options.finalise_min_age_frames = 2;
  options.finalise_every_frames = 2;
  for (const double output_sigmas : {options.fuse_output_sigmas, 1e9}) {
    MapOptions o = options;
    o.fuse_output_sigmas = output_sigmas;
    IncrementalMap map(o);
    MeshDiffer differ;
    MeshAccumulator accumulator;
    std::multiset<std::array<double, 9>> written;  // the finalised pieces, then the live mesh at the end
    std::mt19937 rng(5);
    std::size_t output_moved = 0;
    for (int f = 0; f < 24; ++f) {
      output_moved += map.Update(fusion_test::NoisyStreetFrame(scene, 1.0 * f, kDisparitySigmaPx, &rng))
                          .vertices_output_moved;
      const IdentifiedMesh frozen = map.TakeFinalisedMesh();
      const auto finalised = OrientedTriangles(frozen.mesh);
      written.insert(finalised.begin(), finalised.end());
      accumulator.Apply(differ.Update(f, map.ExtractIdentifiedMesh(), frozen));
    }
    std::multiset<std::array<double, 9>> expected = written;
    const auto live = OrientedTriangles(map.ExtractMesh());
    expected.insert(live.begin(), live.end());
    EXPECT_TRUE(OrientedTriangles(accumulator.ToMesh()) == expected)
        << "fuse_output_sigmas " << output_sigmas;
    EXPECT_GT(written.size(), 100u) << "no seam of finalisation";
    if (output_sigmas < 1e9) {
      EXPECT_GT(output_moved, 100u);
    } else {
      EXPECT_EQ(output_moved, 0u);
    }
  }
}

// A point floating in the street's free space (an SGBM mismatch, seen in one frame only) becomes a vertex;
// the later views see the street through it and it leaves the map. With map.outlier_sightings: 0 it stays.
TEST(IncrementalMap, AVertexTheViewsSeeThroughLeavesTheMap) {
  const test::StreetScene scene;
  MapOptions options;
  options.visibility = Visibility::kDepth;
  options.disparity_sigma_px = 0.01;
  options.confirm_beyond_m = 0.0;
  MapOptions keep = options;
  keep.outlier_sightings = 0;
  IncrementalMap map(options), kept_map(keep);
  const Eigen::Vector3d floating(0.0, 12.0, 3.0);  // 12 m ahead, 1.4 m above the camera, mid-street
  std::size_t outliers = 0;
  for (int f = 0; f < 8; ++f) {
    LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    if (f == 0) {
      // The first frame's depth map and points see the floating point at its pixel.
      auto view = std::make_shared<DepthView>(*frame.camera_views[0]);
      view->depth_m = view->depth_m.clone();
      const Eigen::Vector3d p_cam = view->world_from_cam.inverse() * floating;
      const Eigen::Vector2d uv = view->intrinsics.Project(p_cam);
      view->depth_m.at<float>(int(std::lround(uv.y())), int(std::lround(uv.x()))) = float(p_cam.z());
      frame.camera_views[0] = view;
      frame.positions_world.push_back(floating);
      frame.labels.push_back(frame.labels.front());
      frame.camera_index.push_back(0);
    }
    outliers += map.Update(frame).vertices_outliers;
    kept_map.Update(frame);
  }
  // Whether a vertex of the triangulation lies at the floating point (read off its cells' corners).
  const auto near_floating = [&](const IncrementalMap& m) {
    for (const CellVotes& c : m.CellVotesSnapshot()) {
      for (const Eigen::Vector3d& p : c.vertices) {
        if ((p - floating).norm() < 0.3) return 1;
      }
    }
    return 0;
  };
  EXPECT_EQ(near_floating(kept_map), 1) << "without the outlier rule the mismatch stays";
  EXPECT_EQ(near_floating(map), 0);
  EXPECT_GE(outliers, 1u);
  EXPECT_EQ(map.Statistics().vertices_outliers, outliers);
}

}  // namespace
}  // namespace semap
