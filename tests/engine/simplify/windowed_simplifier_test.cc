#include "engine/simplify/windowed_simplifier.h"

#include <gtest/gtest.h>

#include "tests/engine/simplify/scene.h"

namespace semap {
namespace {

// Frame n of a synthetic drive along +x at 1 m per frame: the camera sees the road in [n − 1, n + 7] and a
// building wall on its left, freshly sampled each frame (different jitter), so consecutive frames overlap
// by 7/8 like a real stereo sequence; a box (car) sits in the first frames' view.
LabelledCloud StreamFrame(int n) {
  test::SceneOptions o;
  o.x_min = n - 1.0;
  o.x_max = n + 7.0;
  o.y_min = -3.0;
  o.y_max = 3.0;
  o.with_wall = false;
  o.with_box = n <= 3;
  o.camera = {n - 2.0, 0.0, 1.7};
  o.seed = 100 + n;
  o.spacing_m = 0.07;
  LabelledCloud c = test::MakeScene(o);
  // Wall along y = 3 (label building), x in the frame's range.
  std::mt19937_64 rng(200 + n);
  std::uniform_real_distribution<double> j(-0.01, 0.01);
  for (double x = o.x_min; x < o.x_max; x += o.spacing_m) {
    for (double z = o.spacing_m; z < 2.0; z += o.spacing_m) {
      c.positions_world.push_back({x + j(rng), 3.0, z + j(rng)});
      c.labels.push_back(test::kBuilding);
      c.camera_index.push_back(0);
    }
  }
  c.camera_frame_ids = {n};
  return c;
}

double Share(const SimplifyResult& r, Label label) {
  for (const auto& s : r.per_class) {
    if (s.label == label) return static_cast<double>(s.kept) / static_cast<double>(s.in);
  }
  return -1.0;
}

TEST(WindowedSimplifier, NewPointsOnDecidedAreasMostlyGo) {
  for (auto method : {SimplifyMethod::kLinearRadius, SimplifyMethod::kProbabilistic}) {
    SCOPED_TRACE(SimplifyMethodName(method));
    SimplifyOptions o;
    o.method = method;
    o.window_frames = 8;  // covers the 8-frame overlap of the drive (see the class comment)
    WindowedSimplifier ws(o, ClassMap::Cityscapes());
    std::vector<double> road_share, wall_share;
    for (int n = 0; n < 10; ++n) {
      const LabelledCloud frame = StreamFrame(n);
      const auto out = ws.Process(frame);
      road_share.push_back(Share(out.result, test::kRoad));
      wall_share.push_back(Share(out.result, test::kBuilding));
      // Non-target points pass through unchanged.
      if (n <= 3) {
        EXPECT_DOUBLE_EQ(Share(out.result, test::kCar), 1.0);
      }
      EXPECT_EQ(out.kept.size(), out.result.kept());
      out.kept.AssertConsistent();
      RecordProperty(std::string(SimplifyMethodName(method)) + "_road_share_" + std::to_string(n),
                     std::to_string(road_share.back()));
      RecordProperty(std::string(SimplifyMethodName(method)) + "_wall_share_" + std::to_string(n),
                     std::to_string(wall_share.back()));
    }
    // The first frame alone keeps about the target share; later frames overlap decided ground by 7/8.
    // LS's quota and PS's streaming gate count the decided points, so only the newly seen 1/8 strip keeps
    // about c̄ (measured: LSR 0.39 then 0.04-0.06, PS 0.41 then 0.05-0.06 per frame).
    const double factor = 0.25;
    for (int n = 1; n < 10; ++n) {
      EXPECT_LT(road_share[n], factor * road_share[0]) << "frame " << n;
      EXPECT_LT(wall_share[n], factor * wall_share[0]) << "frame " << n;
    }
    EXPECT_EQ(ws.frames_processed(), 10u);
    std::uint64_t in = 0;
    for (const auto& t : ws.totals()) in += t.in;
    EXPECT_GT(in, 0u);
  }
}

TEST(WindowedSimplifier, ReplayIsDeterministicAndResetForgets) {
  SimplifyOptions o;
  o.method = SimplifyMethod::kProbabilistic;
  WindowedSimplifier a(o, ClassMap::Cityscapes());
  WindowedSimplifier b(o, ClassMap::Cityscapes());
  for (int n = 0; n < 3; ++n) {
    const auto frame = StreamFrame(n);
    EXPECT_EQ(a.Process(frame).result.kept_indices, b.Process(frame).result.kept_indices);
  }
  a.Reset();
  EXPECT_EQ(a.frames_processed(), 0u);
  EXPECT_TRUE(a.totals().empty());
  WindowedSimplifier fresh(o, ClassMap::Cityscapes());
  const auto frame = StreamFrame(5);
  EXPECT_EQ(a.Process(frame).result.kept_indices, fresh.Process(frame).result.kept_indices);
}

}  // namespace
}  // namespace semap
