// `semap segment` run as a user would: ENet on a real KITTI frame, and bad input.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap {
namespace {

constexpr const char* kSubset = "data/kitti_stereo2015_subset";
constexpr const char* kModel = "models/enet-cityscapes/enet-model.net";

TEST(SemapSegment, WritesLabelPngAndOverlay) {
  SEMAP_REQUIRE_SHARED(kSubset);
  SEMAP_REQUIRE_SHARED(kModel);
  const auto out = test::TempDir() / "out";
  const auto r = test::RunSemap("segment " + (test::SharedDir() / kSubset).string() + " --frame 57 --out " +
                                out.string() +
                                " --set semantics.enet_model_path=" + (test::SharedDir() / kModel).string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat labels = cv::imread((out / "labels_000057.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(labels.type(), CV_8UC1);
  EXPECT_EQ(labels.size(), cv::Size(1242, 375));
  double max_id = 0;
  cv::minMaxLoc(labels, nullptr, &max_id);
  EXPECT_LT(max_id, 20);
  const cv::Mat overlay = cv::imread((out / "overlay_000057.png").string(), cv::IMREAD_COLOR);
  EXPECT_EQ(overlay.size(), cv::Size(1242, 375));
  EXPECT_TRUE(r.Has("Vegetation")) << r.output;
}

TEST(SemapSegment, BadModelGivesMessageAndExitCode) {
  SEMAP_REQUIRE_SHARED(kSubset);
  const auto dir = test::TempDir();
  const auto r = test::RunSemap(
      "segment " + (test::SharedDir() / kSubset).string() + " --frame 2 --out " + (dir / "o").string() +
      " --set semantics.enet_model_path=" + (test::SharedDir() / kSubset / "calib_cam_to_cam.txt").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.Has("not a Torch7 network")) << r.output;
}

}  // namespace
}  // namespace semap
