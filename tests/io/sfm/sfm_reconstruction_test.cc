// The common reconstruction struct: format names, canonical observation order, reading by format, and the
// ParseError message (io/file_error.h).
#include "io/sfm/sfm_reconstruction.h"

#include <gtest/gtest.h>

#include "io/sfm/colmap.h"
#include "io/sfm/openmvg.h"
#include "io/sfm/slam_json.h"
#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

TEST(SfmReconstruction, FormatNames) {
  for (SfmFormat f : {SfmFormat::kColmap, SfmFormat::kOpenMvg, SfmFormat::kSlamJson}) {
    EXPECT_EQ(SfmFormatFromName(SfmFormatName(f)), f);
  }
  EXPECT_STREQ(SfmFormatName(SfmFormat::kSlamJson), "slam-json");
  try {
    SfmFormatFromName("bundler");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bundler'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("colmap, openmvg, slam-json"), std::string::npos);
  }
}

TEST(SfmReconstruction, SortsObservationsByPointThenView) {
  SfmReconstruction r;
  r.views.resize(3);
  r.point_ids = {1, 2};
  r.points_world.resize(2, Eigen::Vector3d::Zero());
  r.observations = {{1, 2, {1, 1}}, {0, 1, {2, 2}}, {1, 0, {3, 3}}, {0, 1, {4, 4}}};
  r.SortObservations();
  r.AssertConsistent();
  ASSERT_EQ(r.observations.size(), 4u);
  EXPECT_EQ(r.observations[0].pixel_px.x(), 2);  // (0, 1), stable: first of the equal pair
  EXPECT_EQ(r.observations[1].pixel_px.x(), 4);
  EXPECT_EQ(r.observations[2].pixel_px.x(), 3);  // (1, 0)
  EXPECT_EQ(r.observations[3].pixel_px.x(), 1);  // (1, 2)
}

TEST(SfmReconstruction, FindsIntrinsicsById) {
  SfmReconstruction r;
  r.intrinsics = {{4, "pinhole", 1, 1, {1, 0, 0}}, {7, "pinhole", 2, 2, {2, 0, 0}}};
  ASSERT_NE(r.FindIntrinsics(7), nullptr);
  EXPECT_EQ(r.FindIntrinsics(7)->width_px, 2);
  EXPECT_EQ(r.FindIntrinsics(kNoIntrinsics), nullptr);
}

TEST(SfmReconstruction, ReadsEachFormatByName) {
  SfmReconstruction scene = test::SmallStreet();
  const auto dir = test::TempDir();
  WriteColmapModel(dir / "colmap", scene, ColmapEncoding::kBinary);
  test::ExpectSameScene(scene, ReadSfm(dir / "colmap", SfmFormat::kColmap), 1e-12);
  scene.point_colors_rgb.clear();
  WriteOpenMvgJson(dir / "sfm_data.json", scene);
  test::ExpectSameScene(scene, ReadSfm(dir / "sfm_data.json", SfmFormat::kOpenMvg), 0.0);
  WriteSlamJson(dir / "slam.json", scene);
  test::ExpectSameScene(scene, ReadSfm(dir / "slam.json", SfmFormat::kSlamJson), 0.0);
  // The wrong reader names what it misses.
  test::ExpectReadError([&] { ReadSfm(dir / "slam.json", SfmFormat::kOpenMvg); },
                        {"slam.json", "sfm_data_version: missing"});
}

TEST(ParseError, NamesFileEntryAndField) {
  const ParseError e("a/b.json", "views[3] (viewId 7)", "extrinsic.center", "missing");
  EXPECT_STREQ(e.what(), "a/b.json: views[3] (viewId 7): extrinsic.center: missing");
  EXPECT_EQ(e.entry(), "views[3] (viewId 7)");
  EXPECT_EQ(e.field(), "extrinsic.center");
  EXPECT_EQ(e.path(), std::filesystem::path("a/b.json"));
  EXPECT_STREQ(ParseError("f.txt", "line 2", "", "bad").what(), "f.txt: line 2: bad");
}

}  // namespace
}  // namespace semap::io
