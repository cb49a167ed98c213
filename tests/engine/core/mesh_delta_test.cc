#include "engine/core/mesh_delta.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

namespace semap {
namespace {

// A triangle as the set-comparable triple of its vertex positions, rotated canonically.
using PosTriangle = std::array<std::array<double, 3>, 3>;

std::multiset<PosTriangle> TrianglesOf(const Mesh& m) {
  std::multiset<PosTriangle> out;
  for (const auto& t : m.triangles) {
    PosTriangle p;
    for (int k = 0; k < 3; ++k) {
      const auto& v = m.vertices[t[k]];
      p[k] = {v.x(), v.y(), v.z()};
    }
    const int first = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
    out.insert({p[first], p[(first + 1) % 3], p[(first + 2) % 3]});
  }
  return out;
}

// A mesh over vertex ids: vertex id i sits at (i, i², 1) so positions identify ids.
IdentifiedMesh MakeMesh(const std::vector<std::array<VertexId, 3>>& tris) {
  IdentifiedMesh m;
  std::map<VertexId, std::uint32_t> index;
  for (const auto& t : tris) {
    std::array<std::uint32_t, 3> local{};
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = index.emplace(t[k], static_cast<std::uint32_t>(m.vertex_ids.size()));
      if (inserted) {
        const double x = static_cast<double>(t[k]);
        m.vertex_ids.push_back(t[k]);
        m.mesh.vertices.emplace_back(x, x * x, 1.0);
        m.mesh.labels.push_back(static_cast<Label>(t[k] % 20));
      }
      local[k] = it->second;
    }
    m.mesh.triangles.push_back(local);
  }
  return m;
}

// A delta adding `tris` with ids `ids`, and their vertices (id i at (i, i², 1)).
MeshDelta MakeDelta(const std::vector<std::array<VertexId, 3>>& tris, const std::vector<TriangleId>& ids) {
  const IdentifiedMesh m = MakeMesh(tris);
  MeshDelta d;
  d.vertex_ids = m.vertex_ids;
  d.vertex_positions = m.mesh.vertices;
  d.vertex_labels = m.mesh.labels;
  d.added_triangle_ids = ids;
  d.added_triangles = tris;
  return d;
}

TEST(MeshDiffer, FirstUpdateAddsEverythingAndSecondIsEmpty) {
  MeshDiffer differ;
  const auto m = MakeMesh({{1, 2, 3}, {2, 3, 4}});
  const auto d1 = differ.Update(0, m);
  EXPECT_EQ(d1.added_triangle_ids.size(), 2u);
  EXPECT_EQ(d1.vertex_ids.size(), 4u);
  EXPECT_TRUE(d1.removed_triangle_ids.empty());
  const auto d2 = differ.Update(1, m);
  EXPECT_TRUE(d2.empty());
}

TEST(MeshDiffer, RotationIsTheSameTriangleButFlipIsNot) {
  MeshDiffer differ;
  differ.Update(0, MakeMesh({{1, 2, 3}}));
  EXPECT_TRUE(differ.Update(1, MakeMesh({{2, 3, 1}})).empty());
  const auto flipped = differ.Update(2, MakeMesh({{1, 3, 2}}));
  EXPECT_EQ(flipped.added_triangle_ids.size(), 1u);
  EXPECT_EQ(flipped.removed_triangle_ids.size(), 1u);
}

TEST(MeshDiffer, FrozenTrianglesAreNeverRemoved) {
  MeshDiffer differ;
  MeshAccumulator acc;
  acc.Apply(differ.Update(0, MakeMesh({{1, 2, 3}, {4, 5, 6}})));
  // {1,2,3} is finalised: it leaves the live mesh but must stay in the subscriber's.
  acc.Apply(differ.Update(1, MakeMesh({{4, 5, 6}}), MakeMesh({{1, 2, 3}})));
  EXPECT_EQ(acc.num_triangles(), 2u);
  EXPECT_EQ(differ.num_live_triangles(), 1u);
}

TEST(MeshDiffer, DeltasNameTheFinalisedTriangles) {
  MeshDiffer differ;
  const MeshDelta first = differ.Update(0, MakeMesh({{1, 2, 3}, {4, 5, 6}}));
  EXPECT_TRUE(first.finalised_triangle_ids.empty());
  // {1,2,3} was published while live and keeps its id; {7,8,9} is finalised before ever being live.
  const MeshDelta second = differ.Update(1, MakeMesh({{4, 5, 6}}), MakeMesh({{1, 2, 3}, {7, 8, 9}}));
  ASSERT_EQ(second.added_triangle_ids.size(), 1u);
  EXPECT_TRUE(second.removed_triangle_ids.empty());
  const std::set<TriangleId> finalised(second.finalised_triangle_ids.begin(),
                                       second.finalised_triangle_ids.end());
  const TriangleId id_123 = first.added_triangles[0] == std::array<VertexId, 3>{1, 2, 3}
                                ? first.added_triangle_ids[0]
                                : first.added_triangle_ids[1];
  EXPECT_EQ(finalised, (std::set<TriangleId>{id_123, second.added_triangle_ids[0]}));
}

TEST(MeshDeltaProperty, AccumulatedDeltasEqualLiveMeshPlusFrozen) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    MeshDiffer differ;
    MeshAccumulator acc;
    std::set<std::array<VertexId, 3>> live;
    std::vector<std::array<VertexId, 3>> all_frozen;
    for (int step = 0; step < 30; ++step) {
      // Random edits: remove some live triangles, freeze some, add new ones over a growing id range.
      std::vector<std::array<VertexId, 3>> frozen_now;
      for (auto it = live.begin(); it != live.end();) {
        const int r = static_cast<int>(rng() % 10);
        if (r == 0) {
          it = live.erase(it);
        } else if (r == 1) {
          frozen_now.push_back(*it);
          it = live.erase(it);
        } else {
          ++it;
        }
      }
      const int adds = static_cast<int>(rng() % 6);
      for (int a = 0; a < adds; ++a) {
        const VertexId base = 3 * (step * 10 + a) + 1;
        live.insert({base, base + 1 + rng() % 2, base + 3 + rng() % 2});
      }
      all_frozen.insert(all_frozen.end(), frozen_now.begin(), frozen_now.end());
      const std::vector<std::array<VertexId, 3>> live_list(live.begin(), live.end());
      acc.Apply(differ.Update(step, MakeMesh(live_list), MakeMesh(frozen_now)));

      auto expected = live_list;
      expected.insert(expected.end(), all_frozen.begin(), all_frozen.end());
      const Mesh got = acc.ToMesh();
      ASSERT_TRUE(got.IsConsistent());
      ASSERT_EQ(TrianglesOf(got), TrianglesOf(MakeMesh(expected).mesh))
          << "trial " << trial << " step " << step;
      // Labels travel with their vertices.
      for (size_t i = 0; i < got.vertices.size(); ++i) {
        ASSERT_EQ(got.labels[i], static_cast<Label>(static_cast<VertexId>(got.vertices[i].x()) % 20));
      }
    }
  }
}

TEST(MeshAccumulator, UnknownRemovalsAreIgnored) {
  MeshAccumulator acc;
  MeshDelta d;
  d.removed_triangle_ids = {42};
  acc.Apply(d);
  EXPECT_EQ(acc.num_triangles(), 0u);
  EXPECT_TRUE(acc.ToMesh().vertices.empty());
}

TEST(MeshAccumulator, ForgetsTheVerticesNoTriangleReferences) {
  // A live mesh that moves along: the accumulator holds the vertices of its triangles only, not every vertex
  // it was ever sent.
  MeshDiffer differ;
  MeshAccumulator acc;
  for (VertexId first = 0; first < 200; ++first) {
    acc.Apply(differ.Update(std::int64_t(first),
                            MakeMesh({{first, first + 1, first + 2}, {first + 1, first + 3, first + 2}})));
    ASSERT_EQ(acc.num_triangles(), 2u);
    ASSERT_EQ(acc.num_vertices(), 4u);
  }
}

TEST(MeshAccumulator, TakeTrianglesReturnsThemWithTheirVerticesAndKeepsTheShared) {
  MeshAccumulator acc;
  MeshDelta d;
  d.vertex_ids = {1, 2, 3, 4};
  d.vertex_positions = {{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  d.vertex_labels = {1, 2, 3, 4};
  d.added_triangle_ids = {10, 11};
  d.added_triangles = {{{1, 2, 3}}, {{2, 4, 3}}};
  acc.Apply(d);
  const MeshDelta taken = acc.TakeTriangles({10, 99});  // 99: unknown, passed over
  ASSERT_EQ(taken.added_triangle_ids, std::vector<TriangleId>{10});
  EXPECT_EQ(taken.added_triangles[0], (std::array<VertexId, 3>{1, 2, 3}));
  EXPECT_EQ(taken.vertex_ids, (std::vector<VertexId>{1, 2, 3}));
  EXPECT_EQ(taken.vertex_labels, (std::vector<Label>{1, 2, 3}));
  EXPECT_TRUE(taken.vertex_colors_rgb.empty());  // the accumulator never had colours
  // Vertex 1 was on the taken triangle only; 2 and 3 stay with triangle 11.
  EXPECT_EQ(acc.num_triangles(), 1u);
  EXPECT_EQ(acc.num_vertices(), 3u);
  const Mesh rest = acc.ToMesh();
  ASSERT_EQ(rest.num_vertices(), 3u);
  EXPECT_EQ(rest.vertices[0].x(), 2.0);
  EXPECT_TRUE(acc.TakeTriangles({10}).added_triangle_ids.empty());  // taken once
}

TEST(MeshAccumulator, ApplyingAnIdAgainReplacesItsTriangle) {
  MeshAccumulator acc;
  acc.Apply(MakeDelta({{1, 2, 3}}, {5}));
  acc.Apply(MakeDelta({{4, 5, 6}}, {5}));
  EXPECT_EQ(acc.num_triangles(), 1u);
  EXPECT_EQ(acc.num_vertices(), 3u);  // 1, 2, 3 went with the triangle they were on
  EXPECT_EQ(acc.ToMesh().vertices[0].x(), 4.0);
}

}  // namespace
}  // namespace semap
