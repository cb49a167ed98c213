#include "engine/sim/scene.h"

#include <gtest/gtest.h>

#include <set>

#include "engine/sim/trajectory.h"

namespace semap::sim {
namespace {

SynthOptions Opts(ScenePreset preset, std::uint64_t seed) {
  SynthOptions o;
  o.preset = preset;
  o.num_frames = 60;
  o.seed = seed;
  return o;
}

Scene Build(const SynthOptions& o) { return BuildScene(o, Trajectory::Generate(o, 0.93)); }

std::map<Label, double> AreaByLabel(const Scene& s) {
  std::map<Label, double> area;
  for (size_t t = 0; t < s.num_triangles(); ++t) {
    const auto& tri = s.triangles[t];
    area[s.labels[t]] +=
        0.5 * (s.vertices[tri[1]] - s.vertices[tri[0]]).cross(s.vertices[tri[2]] - s.vertices[tri[0]]).norm();
  }
  return area;
}

TEST(Scene, ConsistentArraysChunksAndLabels) {
  const Scene s = Build(Opts(ScenePreset::kMixed, 3));
  const size_t n = s.num_triangles();
  ASSERT_GT(n, 1000u);
  EXPECT_EQ(s.normals.size(), n);
  EXPECT_EQ(s.labels.size(), n);
  EXPECT_EQ(s.materials.size(), n);
  EXPECT_EQ(s.object_ids.size(), n);
  size_t covered = 0;
  for (const auto& c : s.chunks) {
    EXPECT_EQ(c.first, covered);
    for (std::uint32_t t = c.first; t < c.first + c.count; ++t) {
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(c.box.contains(s.vertices[s.triangles[t][k]]));
    }
    covered += c.count;
  }
  EXPECT_EQ(covered, n);
  // Every class a street needs is present.
  std::set<Label> labels(s.labels.begin(), s.labels.end());
  for (Label l : {label::kRoad, label::kSidewalk, label::kBuilding, label::kFence, label::kPole,
                  label::kTrafficSign, label::kVegetation, label::kTerrain, label::kCar}) {
    EXPECT_TRUE(labels.count(l)) << "label " << int(l);
  }
  // Unit normals consistent with the winding.
  for (size_t t = 0; t < n; t += 97) {
    const auto& tri = s.triangles[t];
    const Eigen::Vector3d nn =
        (s.vertices[tri[1]] - s.vertices[tri[0]]).cross(s.vertices[tri[2]] - s.vertices[tri[0]]).normalized();
    EXPECT_NEAR(nn.dot(s.normals[t].cast<double>()), 1.0, 1e-5);
  }
}

TEST(Scene, MeshVertexLabelsAreExactAndTransformed) {
  const Scene s = Build(Opts(ScenePreset::kUrban, 1));
  Pose3d out_from_scene = Pose3d::Identity();
  out_from_scene.translation() = Eigen::Vector3d(1, 2, 3);
  const Mesh m = s.ToMesh(out_from_scene);
  ASSERT_TRUE(m.IsConsistent());
  ASSERT_EQ(m.labels.size(), m.vertices.size());
  for (size_t t = 0; t < s.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(m.labels[s.triangles[t][k]], s.labels[t]) << "triangle " << t;
  }
  EXPECT_TRUE(m.vertices[5].isApprox(s.vertices[5] + Eigen::Vector3d(1, 2, 3)));
}

TEST(Scene, SameSeedSameSceneOtherSeedOtherScene) {
  const Scene a = Build(Opts(ScenePreset::kMixed, 7)), b = Build(Opts(ScenePreset::kMixed, 7));
  ASSERT_EQ(a.num_triangles(), b.num_triangles());
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.labels, b.labels);
  const Scene c = Build(Opts(ScenePreset::kMixed, 8));
  EXPECT_FALSE(c.vertices == a.vertices);
}

TEST(Scene, PresetsDifferInComposition) {
  auto urban = AreaByLabel(Build(Opts(ScenePreset::kUrban, 2)));
  auto veg = AreaByLabel(Build(Opts(ScenePreset::kVegetated, 2)));
  // Building surface dominates the urban scene, vegetation and cars the vegetated one.
  EXPECT_GT(urban[label::kBuilding], 2.0 * veg[label::kBuilding]);
  EXPECT_GT(veg[label::kVegetation], 2.0 * urban[label::kVegetation]);
  EXPECT_GT(veg[label::kCar], urban[label::kCar]);
}

}  // namespace
}  // namespace semap::sim
