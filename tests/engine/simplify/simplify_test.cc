// The methods on the synthetic road + box + wall scene.
#include "engine/simplify/simplify.h"

#include <gtest/gtest.h>

#include <map>

#include "engine/core/check.h"
#include "tests/engine/simplify/scene.h"

namespace semap {
namespace {

using test::kBuilding;
using test::kCar;
using test::kRoad;

const ClassSimplifyStats* StatsOf(const SimplifyResult& r, Label label) {
  for (const auto& s : r.per_class) {
    if (s.label == label) return &s;
  }
  return nullptr;
}

double KeptShare(const SimplifyResult& r, Label label) {
  const auto* s = StatsOf(r, label);
  return s && s->in > 0 ? static_cast<double>(s->kept) / static_cast<double>(s->in) : 1.0;
}

SimplifyOptions WithMethod(SimplifyMethod m) {
  SimplifyOptions o;
  o.method = m;
  return o;
}

TEST(SimplifyMethods, NamesRoundTripAndUnknownNameThrows) {
  EXPECT_EQ(AllSimplifyMethods().size(), 14u);
  for (auto m : AllSimplifyMethods()) EXPECT_EQ(SimplifyMethodFromName(SimplifyMethodName(m)), m);
  EXPECT_EQ(SimplifyMethodFromName("ACSK"), SimplifyMethod::kAdaptiveClassKnn);
  EXPECT_THROW(SimplifyMethodFromName("ps"), InvalidOption);
  EXPECT_THROW(SimplifyMethodFromName("LS"), InvalidOption);
}

TEST(SimplifyOptions, CheckRejectsBadValues) {
  SimplifyOptions o;
  EXPECT_NO_THROW(o.Check());
  o.target_conservation = 1.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.region_radius_m = 0.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.min_conservation = 0.5;  // above c̄
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.window_frames = 0;
  try {
    o.Check();
    FAIL() << "no throw";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "window_frames");
  }
}

TEST(Simplify, EveryMethodRunsByNameWithConsistentStatistics) {
  const LabelledCloud cloud = test::MakeScene();
  for (auto m : AllSimplifyMethods()) {
    SCOPED_TRACE(SimplifyMethodName(m));
    const SimplifyResult r = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(m));
    EXPECT_EQ(r.in, cloud.size());
    std::uint64_t in = 0, kept = 0;
    for (const auto& s : r.per_class) {
      EXPECT_EQ(s.in, s.kept + s.removed);
      in += s.in;
      kept += s.kept;
    }
    EXPECT_EQ(in, cloud.size());
    EXPECT_EQ(kept, r.kept());
    EXPECT_TRUE(std::is_sorted(r.kept_indices.begin(), r.kept_indices.end()));
    EXPECT_TRUE(std::adjacent_find(r.kept_indices.begin(), r.kept_indices.end()) == r.kept_indices.end());
    if (m == SimplifyMethod::kOriginal) {
      EXPECT_EQ(r.kept(), cloud.size());
    } else {
      EXPECT_LT(r.kept(), cloud.size()) << "method removed nothing";
      EXPECT_GT(r.kept(), 0u);
    }
    EXPECT_GE(r.time_s, 0.0);
    RecordProperty(std::string("time_s_") + SimplifyMethodName(m), std::to_string(r.time_s));
  }
}

TEST(Simplify, SemanticMethodsLeaveNonTargetClassesBitIdentical) {
  const LabelledCloud cloud = test::MakeScene();
  std::vector<Eigen::Vector3d> cars;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels[i] == kCar) cars.push_back(cloud.positions_world[i]);
  }
  for (auto m : AllSimplifyMethods()) {
    if (!IsSemanticMethod(m)) continue;
    SCOPED_TRACE(SimplifyMethodName(m));
    const SimplifyResult r = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(m));
    const LabelledCloud out = ApplySimplification(cloud, r);
    std::vector<Eigen::Vector3d> out_cars;
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (out.labels[i] == kCar) out_cars.push_back(out.positions_world[i]);
    }
    ASSERT_EQ(out_cars.size(), cars.size());
    for (std::size_t i = 0; i < cars.size(); ++i) ASSERT_EQ(out_cars[i], cars[i]);  // exact, same order
    EXPECT_LT(KeptShare(r, kRoad), 0.8);
    EXPECT_LT(KeptShare(r, kBuilding), 0.8);
  }
}

TEST(Simplify, SameSeedSameOutputOtherSeedOtherOutput) {
  const LabelledCloud cloud = test::MakeScene();
  for (auto m : {SimplifyMethod::kProbabilistic, SimplifyMethod::kLinearRadius,
                 SimplifyMethod::kAdaptiveClassKnn, SimplifyMethod::kGeometricBaseline}) {
    SCOPED_TRACE(SimplifyMethodName(m));
    SimplifyOptions o = WithMethod(m);
    const auto a = Simplify(cloud, ClassMap::Cityscapes(), o);
    const auto b = Simplify(cloud, ClassMap::Cityscapes(), o);
    EXPECT_EQ(a.kept_indices, b.kept_indices);
    o.seed = 1234;
    const auto c = Simplify(cloud, ClassMap::Cityscapes(), o);
    EXPECT_NE(a.kept_indices, c.kept_indices);
  }
}

TEST(Simplify, AdaptiveClassNeverRemovesMoreThanAdaptive) {
  const LabelledCloud cloud = test::MakeScene();
  const std::pair<SimplifyMethod, SimplifyMethod> pairs[] = {
      {SimplifyMethod::kAdaptiveRadius, SimplifyMethod::kAdaptiveClassRadius},
      {SimplifyMethod::kAdaptiveKnn, SimplifyMethod::kAdaptiveClassKnn}};
  for (const auto& [as, acs] : pairs) {
    SCOPED_TRACE(SimplifyMethodName(acs));
    const auto r_as = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(as));
    const auto r_acs = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(acs));
    for (Label l : {kRoad, kBuilding, kCar}) {
      EXPECT_LE(StatsOf(r_acs, l)->removed, StatsOf(r_as, l)->removed) << "label " << int(l);
    }
    // The road touches the box: ACS keeps strictly more there.
    EXPECT_LT(StatsOf(r_acs, kRoad)->removed, StatsOf(r_as, kRoad)->removed);
  }
}

// Kept share of road points within `band_m` of the box footprint and farther than `interior_m`.
std::pair<double, double> BandAndInteriorShares(const LabelledCloud& cloud, const SimplifyResult& r,
                                                double band_m, double interior_m) {
  std::vector<std::uint8_t> kept(cloud.size(), 0);
  for (auto i : r.kept_indices) kept[i] = 1;
  double band_in = 0, band_kept = 0, int_in = 0, int_kept = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels[i] != kRoad) continue;
    const auto& p = cloud.positions_world[i];
    const double d = test::DistanceToFootprint(p.x(), p.y());
    if (d <= band_m) {
      ++band_in;
      band_kept += kept[i];
    } else if (d >= interior_m && std::abs(p.x()) < 3.0 && std::abs(p.y()) < 3.0) {
      ++int_in;  // away from the patch's outer edge (lower density there)
      int_kept += kept[i];
    }
  }
  return {band_kept / band_in, int_kept / int_in};
}

TEST(Simplify, ProbabilisticKeepsMoreNearTheClassBoundary) {
  test::SceneOptions scene;
  scene.with_wall = false;
  const LabelledCloud cloud = test::MakeScene(scene);
  const auto ps = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(SimplifyMethod::kProbabilistic));
  const auto [band, interior] = BandAndInteriorShares(cloud, ps, 0.1, 1.0);
  RecordProperty("band_share", std::to_string(band));
  RecordProperty("interior_share", std::to_string(interior));
  EXPECT_GT(band, 1.5 * interior) << "band " << band << " interior " << interior;
  // Without semantics (PSB) the boundary band gets no such protection.
  const auto psb =
      Simplify(cloud, ClassMap::Cityscapes(), WithMethod(SimplifyMethod::kProbabilisticBaseline));
  const auto [band_b, interior_b] = BandAndInteriorShares(cloud, psb, 0.1, 1.0);
  EXPECT_LT(band_b, band) << "PSB band " << band_b << " interior " << interior_b;
}

TEST(Simplify, RegionMethodsKeepAboutTheTargetShareOfAUniformPlane) {
  test::SceneOptions scene;
  scene.with_box = false;
  scene.with_wall = false;
  const LabelledCloud cloud = test::MakeScene(scene);
  for (auto m :
       {SimplifyMethod::kLinearRadius, SimplifyMethod::kAdaptiveRadius, SimplifyMethod::kLinearKnn}) {
    SCOPED_TRACE(SimplifyMethodName(m));
    const auto r = Simplify(cloud, ClassMap::Cityscapes(), WithMethod(m));
    const double share = KeptShare(r, kRoad);
    // Each region ends with at most ceil(c̄·n) points at average density; overlaps can only lower that.
    EXPECT_LE(share, 0.4 + 0.05);
    EXPECT_GE(share, 0.2);
  }
}

TEST(Simplify, RankingRemovesTiltedPointsFirst) {
  // A flat road with a 0.2 m wide, 4 m long tent-shaped ridge (45° facets): every region containing ridge
  // points also holds more flat points, and the ridge normals deviate from n_l, so LS discards them first.
  test::SceneOptions scene;
  scene.with_box = false;
  scene.with_wall = false;
  scene.jitter_m = 0.0;
  LabelledCloud cloud = test::MakeScene(scene);
  std::vector<std::uint8_t> rough(cloud.size(), 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    auto& p = cloud.positions_world[i];
    if (p.x() > 1.0 && p.x() < 1.2 && p.y() > -2.0 && p.y() < 2.0) {
      const double t = p.x() - 1.0;
      p.z() = t < 0.1 ? t : 0.2 - t;
      rough[i] = 1;
    }
  }
  // The kept shares over six seeds: with 320 ridge points one seed's share varies from 2 % to 24 % (which
  // points the random draws take), far more than any change of the rule would move it.
  constexpr std::uint64_t kSeeds = 6;
  double rough_in = 0, rough_kept = 0, flat_in = 0, flat_kept = 0;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    SimplifyOptions o = WithMethod(SimplifyMethod::kLinearRadius);
    o.seed = seed;
    const auto r = Simplify(cloud, ClassMap::Cityscapes(), o);
    std::vector<std::uint8_t> kept(cloud.size(), 0);
    for (auto i : r.kept_indices) kept[i] = 1;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.positions_world[i];
      if (rough[i]) {
        ++rough_in;
        rough_kept += kept[i];
      } else if (std::abs(p.x()) < 3.0 && std::abs(p.y()) < 3.0 && std::abs(p.x() - 1.1) > 0.5) {
        ++flat_in;
        flat_kept += kept[i];
      }
    }
  }
  EXPECT_LT(rough_kept / rough_in, 0.5 * flat_kept / flat_in)
      << "rough " << rough_kept / rough_in << " flat " << flat_kept / flat_in;
}

}  // namespace
}  // namespace semap

namespace semap {
namespace {

TEST(Simplify, EmptyUnlabelledAndCameralessClouds) {
  const LabelledCloud empty;
  LabelledCloud unlabelled = test::MakeScene();
  unlabelled.labels.clear();
  LabelledCloud no_cameras = test::MakeScene();
  no_cameras.camera_index.clear();
  no_cameras.camera_centers_world.clear();
  no_cameras.camera_frame_ids.clear();
  for (auto m : AllSimplifyMethods()) {
    SCOPED_TRACE(SimplifyMethodName(m));
    SimplifyOptions o;
    o.method = m;
    const auto r_empty = Simplify(empty, ClassMap::Cityscapes(), o);
    EXPECT_EQ(r_empty.kept(), 0u);
    EXPECT_TRUE(r_empty.per_class.empty());
    // Without labels every point is "Unlabeled" (role keep): semantic methods keep everything.
    const auto r_unlabelled = Simplify(unlabelled, ClassMap::Cityscapes(), o);
    if (IsSemanticMethod(m)) {
      EXPECT_EQ(r_unlabelled.kept(), unlabelled.size());
    }
    // Without cameras normals are oriented along the class plane: still simplifies the targets.
    const auto r_no_cameras = Simplify(no_cameras, ClassMap::Cityscapes(), o);
    if (IsSemanticMethod(m)) {
      EXPECT_LT(r_no_cameras.kept(), no_cameras.size());
    }
  }
}

}  // namespace
}  // namespace semap
