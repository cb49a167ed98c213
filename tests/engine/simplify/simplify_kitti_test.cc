// Simplification of a real KITTI stereo frame: SGBM depth + ENet labels (first-camera rule) → each method.
#include <gtest/gtest.h>

#include "engine/depth/stereo_depth.h"
#include "engine/pipeline/semap_stages.h"
#include "engine/simplify/simplify.h"
#include "io/frame_source.h"
#include "tests/common/test_data.h"

namespace semap {
namespace {

TEST(SimplifyKitti, RealFrameKeepsNonTargetsAndThinsGroundAndWalls) {
  SEMAP_REQUIRE_SHARED("data/kitti_stereo2015_subset");
  SEMAP_REQUIRE_SHARED("models/enet-cityscapes/enet-model.net");
  io::FrameSourceOptions input;
  input.max_frames = 1;
  auto source = io::OpenFrameSource(test::SharedDir() / "data/kitti_stereo2015_subset", input);
  const auto frame = source->Next();
  ASSERT_TRUE(frame.has_value());
  SemanticsOptions semantics;
  semantics.source = LabelSource::kEnet;
  semantics.enet_model_path = (test::SharedDir() / "models/enet-cityscapes/enet-model.net").string();
  DepthOptions dense;  // the whole frame: this test checks what simplification does to a dense cloud
  dense.max_points_per_frame = 0;
  StereoLabelStage stage(dense, semantics, ClassMap::Cityscapes());
  const LabelledCloud cloud = stage.Process(*frame, nullptr);
  ASSERT_GT(cloud.size(), 10000u);
  const ClassMap classes = ClassMap::Cityscapes();
  RecordProperty("points", std::to_string(cloud.size()));

  for (auto m :
       {SimplifyMethod::kProbabilistic, SimplifyMethod::kLinearRadius, SimplifyMethod::kAdaptiveClassKnn}) {
    SCOPED_TRACE(SimplifyMethodName(m));
    SimplifyOptions o;
    o.method = m;
    const SimplifyResult r = Simplify(cloud, classes, o);
    std::uint64_t target_in = 0, target_kept = 0;
    for (const auto& s : r.per_class) {
      if (classes.IsTarget(s.label)) {
        target_in += s.in;
        target_kept += s.kept;
      } else {
        EXPECT_EQ(s.kept, s.in) << "non-target label " << int(s.label) << " lost points";
      }
      RecordProperty(std::string(SimplifyMethodName(m)) + "_" +
                         (classes.Contains(s.label) ? classes.Get(s.label).name : std::to_string(s.label)),
                     std::to_string(s.kept) + "/" + std::to_string(s.in));
    }
    ASSERT_GT(target_in, 1000u) << "ENet found no ground or walls";
    const double share = static_cast<double>(target_kept) / static_cast<double>(target_in);
    RecordProperty(std::string(SimplifyMethodName(m)) + "_target_share", std::to_string(share));
    RecordProperty(std::string(SimplifyMethodName(m)) + "_time_s", std::to_string(r.time_s));
    EXPECT_LT(share, 0.8);
    EXPECT_GT(share, 0.05);
  }
}

}  // namespace
}  // namespace semap
