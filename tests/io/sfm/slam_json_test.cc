// The 2018 manifold mapper's SLAM JSON: round trip, conventions on a hand-written file as ORB-SLAM's
// exporter writes it, and bad input.
#include "io/sfm/slam_json.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

using test::ExpectReadError;
using test::WriteText;

// Two views; point 4 is seen by both (its position refined in the second), point 5 by the second only.
nlohmann::json TinySlamData() {
  return nlohmann::json::parse(R"({
    "slam_data_version": "0.2",
    "root_path": "/data/seq",
    "intrinsics": [{"intrinsicId": 0, "value": {"polymorphic_id": 0, "polymorphic_name": "pinhole",
      "ptr_wrapper": {"data": {"width": 640, "height": 480, "focal_length": 500.0, "principal_point": [320, 240]}}}}],
    "views": [
      {"viewId": 10, "local_path": "/", "filename": "k10.png", "width": 640, "height": 480, "id_intrinsic": 0,
       "extrinsic": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "center": [0, 0, 0]},
       "observations": [{"pointId": 4, "X": [1, 2, 10], "x": [1.0, 2.0]}]},
      {"viewId": 11, "local_path": "/", "filename": "k11.png", "width": 640, "height": 480, "id_intrinsic": 0,
       "extrinsic": {"rotation": [[0, -1, 0], [1, 0, 0], [0, 0, 1]], "center": [0.5, 0, 0]},
       "observations": [{"pointId": 4, "X": [1.1, 2, 10]}, {"pointId": 5, "X": [3, 3, 12]}]}
    ]
  })");
}

TEST(SlamJson, ReadsTheDocumentedConventions) {
  const SfmReconstruction r = ReadSlamJson(test::WriteJson(TinySlamData(), "slam.json"));
  EXPECT_EQ(r.image_root, "/data/seq");
  ASSERT_EQ(r.intrinsics.size(), 1u);
  EXPECT_EQ(r.intrinsics[0].model, "pinhole");
  EXPECT_EQ(r.intrinsics[0].params, (std::vector<double>{500, 320, 240}));
  ASSERT_EQ(r.views.size(), 2u);
  EXPECT_EQ(r.views[0].id, 10);
  EXPECT_EQ(r.views[0].name, "/k10.png");
  // rotation is world → camera, row by row: the camera's x axis in the world is row 0, (0, −1, 0).
  EXPECT_EQ(r.views[1].center_world(), Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(r.views[1].world_from_cam.linear().col(0), Eigen::Vector3d(0, -1, 0));
  ASSERT_EQ(r.num_points(), 2u);
  EXPECT_EQ(r.point_ids, (std::vector<std::int64_t>{4, 5}));
  EXPECT_EQ(r.points_world[0], Eigen::Vector3d(1.1, 2, 10));  // the latest estimate
  ASSERT_EQ(r.observations.size(), 3u);
  EXPECT_EQ(r.observations[0].view, 0u);
  EXPECT_EQ(r.observations[0].pixel_px, Eigen::Vector2d(1, 2));
  EXPECT_TRUE(r.observations[1].pixel_px.array().isNaN().all());  // no "x"
  EXPECT_TRUE(r.point_labels.empty());
}

TEST(SlamJson, RoundTripWithLabels) {
  SfmReconstruction scene = test::SmallStreet();
  scene.point_colors_rgb.clear();
  scene.observations[2].pixel_px = Eigen::Vector2d::Constant(std::nan(""));
  const auto path = test::TempDir() / "out.json";
  WriteSlamJson(path, scene);
  const SfmReconstruction back = ReadSlamJson(path);
  test::ExpectSameScene(scene, back, 0.0);
  ASSERT_EQ(back.intrinsics.size(), 1u);
  EXPECT_EQ(back.intrinsics[0].model, "pinhole");
  EXPECT_EQ(back.intrinsics[0].params, scene.intrinsics[0].params);
}

TEST(SlamJson, BadInputIsAClearError) {
  const std::vector<test::BadJsonCase> cases = {
      {"version",
       [](nlohmann::json* j) { (*j)["slam_data_version"] = "0.1"; },
       {"slam_data_version", "'0.1'"}},
      {"no version",
       [](nlohmann::json* j) { j->erase("slam_data_version"); },
       {"slam_data_version: missing"}},
      {"missing rotation",
       [](nlohmann::json* j) { (*j)["views"][1]["extrinsic"].erase("rotation"); },
       {"views[1] (viewId 11)", "extrinsic.rotation: missing"}},
      {"non-orthonormal rotation",
       [](nlohmann::json* j) {
         (*j)["views"][1]["extrinsic"]["rotation"][2] = {0, 0.5, 1};
       },
       {"views[1] (viewId 11)", "extrinsic.rotation", "not an orthonormal rotation"}},
      {"rotation with two rows",
       [](nlohmann::json* j) { (*j)["views"][0]["extrinsic"]["rotation"].erase(2); },
       {"views[0] (viewId 10)", "extrinsic.rotation", "3 rows (got 2)"}},
      {"null point coordinate",
       [](nlohmann::json* j) { (*j)["views"][1]["observations"][1]["X"][2] = nullptr; },
       {"views[1] (viewId 11)", "observations[1].X[2]", "must be a number (got null)"}},
      {"missing pointId",
       [](nlohmann::json* j) { (*j)["views"][0]["observations"][0].erase("pointId"); },
       {"views[0] (viewId 10)", "observations[0].pointId: missing"}},
      {"negative pointId",
       [](nlohmann::json* j) { (*j)["views"][0]["observations"][0]["pointId"] = -3; },
       {"views[0] (viewId 10)", "observations[0].pointId", "got -3"}},
      {"unknown intrinsic",
       [](nlohmann::json* j) { (*j)["views"][1]["id_intrinsic"] = 2; },
       {"views[1] (viewId 11)", "id_intrinsic", "intrinsic 2 does not exist"}},
      {"duplicate view",
       [](nlohmann::json* j) { (*j)["views"][1]["viewId"] = 10; },
       {"views[1] (viewId 10)", "view id 10 appears twice"}},
      {"observations not an array",
       [](nlohmann::json* j) { (*j)["views"][0]["observations"] = 3; },
       {"views[0] (viewId 10)", "observations", "must be an array"}},
      {"view not an object",
       [](nlohmann::json* j) { (*j)["views"][0] = 3; },
       {"views[0]", "must be an object"}},
      {"label on some observations only",
       [](nlohmann::json* j) { (*j)["views"][0]["observations"][0]["label"] = 1; },
       {"views[1] (viewId 11)", "observations[0].label", "missing, but earlier observations have one"}},
  };
  test::ExpectBadJsonCases(TinySlamData(), cases, test::TempDir() / "slam.json",
                           [](const auto& path) { ReadSlamJson(path); });
}

TEST(SlamJson, NumbersOutOfRangeAndInvalidJson) {
  const auto path = test::TempDir() / "slam.json";
  std::string text = TinySlamData().dump();
  const std::string from = "[1.1,2,10]";
  ASSERT_NE(text.find(from), std::string::npos);
  WriteText(path, text.replace(text.find(from), from.size(), "[1e999,2,10]"));
  ExpectReadError([&] { ReadSlamJson(path); }, {"slam.json", "not valid JSON", "number overflow"});
  WriteText(path, "{\"slam_data_version\": \"0.3\",");
  ExpectReadError([&] { ReadSlamJson(path); }, {"slam.json", "not valid JSON"});
}

}  // namespace
}  // namespace semap::io
