// OpenMVG sfm_data.json: round trip, the conventions on a hand-written file as OpenMVG writes it (cereal
// polymorphic and pointer ids), and bad input.
#include "io/sfm/openmvg.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

using test::ExpectReadError;
using test::WriteText;

// Three views (the third without pose), two intrinsics of the same type (the second refers to the type by
// id only), one pose rotated 90° about z, one point seen by views 0 and 1.
nlohmann::json TinySfmData() {
  return nlohmann::json::parse(R"({
    "sfm_data_version": "0.3",
    "root_path": "/data/images",
    "views": [
      {"key": 0, "value": {"polymorphic_id": 1073741824, "ptr_wrapper": {"id": 2147483649, "data": {
        "local_path": "", "filename": "a.jpg", "width": 100, "height": 80, "id_view": 0, "id_intrinsic": 0,
        "id_pose": 0}}}},
      {"key": 1, "value": {"polymorphic_id": 1073741824, "ptr_wrapper": {"id": 2147483650, "data": {
        "local_path": "sub/", "filename": "b.jpg", "width": 100, "height": 80, "id_view": 1, "id_intrinsic": 1,
        "id_pose": 1}}}},
      {"key": 2, "value": {"polymorphic_id": 1073741824, "ptr_wrapper": {"id": 2147483651, "data": {
        "local_path": "", "filename": "c.jpg", "width": 100, "height": 80, "id_view": 2,
        "id_intrinsic": 4294967295, "id_pose": 4294967295}}}}
    ],
    "intrinsics": [
      {"key": 0, "value": {"polymorphic_id": 2147483649, "polymorphic_name": "pinhole_radial_k3",
        "ptr_wrapper": {"id": 2147483652, "data": {"width": 100, "height": 80, "focal_length": 90.5,
        "principal_point": [50, 40], "disto_k3": [0.1, 0.01, 0.001]}}}},
      {"key": 1, "value": {"polymorphic_id": 1, "ptr_wrapper": {"id": 2147483653, "data": {"width": 100,
        "height": 80, "focal_length": 91, "principal_point": [51, 41], "disto_k3": [0, 0, 0]}}}}
    ],
    "extrinsics": [
      {"key": 0, "value": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "center": [0, 0, 0]}},
      {"key": 1, "value": {"rotation": [[0, -1, 0], [1, 0, 0], [0, 0, 1]], "center": [1, 2, 3]}}
    ],
    "structure": [
      {"key": 9, "value": {"X": [1.5, 2.5, 3.5], "observations": [
        {"key": 0, "value": {"id_feat": 3, "x": [10, 20]}},
        {"key": 1, "value": {"id_feat": 0, "x": [30, 40]}}]}}
    ],
    "control_points": []
  })");
}

TEST(OpenMvg, ReadsTheDocumentedConventions) {
  const SfmReconstruction r = ReadOpenMvgJson(test::WriteJson(TinySfmData(), "sfm_data.json"));
  EXPECT_EQ(r.image_root, "/data/images");
  ASSERT_EQ(r.intrinsics.size(), 2u);
  EXPECT_EQ(r.intrinsics[0].model, "pinhole_radial_k3");
  EXPECT_EQ(r.intrinsics[0].params, (std::vector<double>{90.5, 50, 40, 0.1, 0.01, 0.001}));
  EXPECT_EQ(r.intrinsics[1].model, "pinhole_radial_k3");  // by type id
  ASSERT_EQ(r.views.size(), 2u);                          // the view without pose is left out
  EXPECT_EQ(r.views[1].id, 1);
  EXPECT_EQ(r.views[1].name, "sub/b.jpg");
  EXPECT_EQ(r.views[1].intrinsics_id, 1);
  // rotation is world → camera, row by row: the camera's x axis in the world is row 0, (0, −1, 0).
  EXPECT_EQ(r.views[1].center_world(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r.views[1].world_from_cam.linear().col(0), Eigen::Vector3d(0, -1, 0));
  EXPECT_EQ(r.views[1].world_from_cam.linear().col(1), Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(r.num_points(), 1u);
  EXPECT_EQ(r.point_ids[0], 9);
  EXPECT_EQ(r.points_world[0], Eigen::Vector3d(1.5, 2.5, 3.5));
  EXPECT_TRUE(r.point_colors_rgb.empty());
  ASSERT_EQ(r.observations.size(), 2u);
  EXPECT_EQ(r.observations[1].view, 1u);
  EXPECT_EQ(r.observations[1].pixel_px, Eigen::Vector2d(30, 40));
}

TEST(OpenMvg, RoundTrip) {
  SfmReconstruction scene = test::SmallStreet();
  scene.point_colors_rgb.clear();                                            // sfm_data.json holds no colours
  scene.observations[3].pixel_px = Eigen::Vector2d::Constant(std::nan(""));  // "x" is left out
  const auto path = test::TempDir() / "out.json";
  WriteOpenMvgJson(path, scene);
  const SfmReconstruction back = ReadOpenMvgJson(path);
  test::ExpectSameScene(scene, back, 0.0);  // the rotation is stored as it is
  ASSERT_EQ(back.intrinsics.size(), 1u);
  EXPECT_EQ(back.intrinsics[0].model, "pinhole");  // COLMAP's SIMPLE_PINHOLE
  EXPECT_EQ(back.intrinsics[0].params, scene.intrinsics[0].params);
  // A second type and a repeated one: polymorphic ids written the cereal way read back.
  scene.intrinsics.push_back({2, "pinhole_radial_k1", 10, 20, {5, 5, 10, 0.5}});
  scene.intrinsics.push_back({3, "pinhole", 10, 20, {6, 5, 10}});
  WriteOpenMvgJson(path, scene);
  const SfmReconstruction back2 = ReadOpenMvgJson(path);
  ASSERT_EQ(back2.intrinsics.size(), 3u);
  EXPECT_EQ(back2.intrinsics[1].model, "pinhole_radial_k1");
  EXPECT_EQ(back2.intrinsics[2].model, "pinhole");
  EXPECT_EQ(back2.intrinsics[2].params, (std::vector<double>{6, 5, 10}));
}

TEST(OpenMvg, BadInputIsAClearError) {
  const std::vector<test::BadJsonCase> cases = {
      {"version", [](nlohmann::json* j) { (*j)["sfm_data_version"] = "9.9"; }, {"sfm_data_version", "'9.9'"}},
      {"missing views", [](nlohmann::json* j) { j->erase("views"); }, {"views: missing"}},
      {"missing centre",
       [](nlohmann::json* j) { (*j)["extrinsics"][1]["value"].erase("center"); },
       {"extrinsics[1] (key 1)", "value.center: missing"}},
      {"non-orthonormal rotation",
       [](nlohmann::json* j) {
         (*j)["extrinsics"][1]["value"]["rotation"][0] = {0, -2, 0};
       },
       {"extrinsics[1] (key 1)", "value.rotation", "not an orthonormal rotation"}},
      {"reflection",
       [](nlohmann::json* j) {
         (*j)["extrinsics"][0]["value"]["rotation"][2] = {0, 0, -1};
       },
       {"extrinsics[0] (key 0)", "value.rotation", "determinant -1"}},
      {"null coordinate (NaN as nlohmann writes it)",
       [](nlohmann::json* j) { (*j)["structure"][0]["value"]["X"][1] = nullptr; },
       {"structure[0] (key 9)", "value.X[1]", "must be a number (got null)"}},
      {"huge coordinate",
       [](nlohmann::json* j) { (*j)["structure"][0]["value"]["X"][1] = 1e308 * 10; },
       {"structure[0] (key 9)", "value.X[1]"}},
      {"short centre",
       [](nlohmann::json* j) {
         (*j)["extrinsics"][1]["value"]["center"] = {1, 2};
       },
       {"value.center", "3 numbers (got 2)"}},
      {"observation of a view that does not exist",
       [](nlohmann::json* j) { (*j)["structure"][0]["value"]["observations"][1]["key"] = 7; },
       {"structure[0] (key 9)", "value.observations[1].key", "view 7 does not exist"}},
      {"observation of a view without pose",
       [](nlohmann::json* j) { (*j)["structure"][0]["value"]["observations"][1]["key"] = 2; },
       {"structure[0] (key 9)", "value.observations[1].key", "view 2 has no pose"}},
      {"unknown intrinsic",
       [](nlohmann::json* j) { (*j)["views"][0]["value"]["ptr_wrapper"]["data"]["id_intrinsic"] = 5; },
       {"views[0] (key 0)", "id_intrinsic", "intrinsic 5 does not exist"}},
      {"duplicate point",
       [](nlohmann::json* j) { (*j)["structure"].push_back((*j)["structure"][0]); },
       {"structure[1] (key 9)", "point id 9 appears twice"}},
      {"type id never introduced",
       [](nlohmann::json* j) { (*j)["intrinsics"][1]["value"]["polymorphic_id"] = 4; },
       {"intrinsics[1] (key 1)", "value.polymorphic_id", "type id 4"}},
      {"missing distortion",
       [](nlohmann::json* j) { (*j)["intrinsics"][0]["value"]["ptr_wrapper"]["data"].erase("disto_k3"); },
       {"intrinsics[0] (key 0)", "disto_k3: missing"}},
      {"string instead of integer",
       [](nlohmann::json* j) { (*j)["structure"][0]["key"] = "9"; },
       {"structure[0]", "key", "must be an integer"}},
      {"label on some points only",
       [](nlohmann::json* j) {
         (*j)["structure"].push_back((*j)["structure"][0]);
         (*j)["structure"][1]["key"] = 10;
         (*j)["structure"][0]["value"]["label"] = 3;
       },
       {"structure[1] (key 10)", "value.label", "missing, but earlier points have one"}},
  };
  test::ExpectBadJsonCases(TinySfmData(), cases, test::TempDir() / "sfm_data.json",
                           [](const auto& path) { ReadOpenMvgJson(path); });
}

TEST(OpenMvg, AMissingArrayIsNamedNotTheEntryReadBeforeIt) {
  nlohmann::json j = TinySfmData();
  j.erase("structure");
  const auto path = test::TempDir() / "sfm_data.json";
  WriteText(path, j.dump());
  try {
    ReadOpenMvgJson(path);
    FAIL() << "expected a ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": structure: missing") << e.what();
  }
}

TEST(OpenMvg, InvalidJsonAndMissingFile) {
  const auto path = test::TempDir() / "sfm_data.json";
  WriteText(path, R"({"sfm_data_version": "0.3", "views": [ NaN ]})");
  ExpectReadError([&] { ReadOpenMvgJson(path); }, {"sfm_data.json", "not valid JSON"});
  ExpectReadError([&] { ReadOpenMvgJson(test::TempDir() / "none.json"); }, {"none.json", "file not found"});
}

TEST(OpenMvg, LabelsRoundTripAndWriterRefusesUnknownModels) {
  SfmReconstruction scene = test::SmallStreet();
  scene.point_colors_rgb.clear();
  const auto path = test::TempDir() / "out.json";
  WriteOpenMvgJson(path, scene);
  EXPECT_EQ(ReadOpenMvgJson(path).point_labels, scene.point_labels);
  scene.intrinsics[0] = {1, "OPENCV", 100, 80, {1, 2, 3, 4, 5, 6, 7, 8}};
  EXPECT_THROW(WriteOpenMvgJson(path, scene), std::invalid_argument);
}

}  // namespace
}  // namespace semap::io
