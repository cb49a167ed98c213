// COLMAP models: text and binary round trips, the file conventions on a hand-written model, and every kind of
// bad input.
#include "io/sfm/colmap.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

using test::ExpectReadError;
using test::WriteText;

// One camera, one image (IMAGE_ID 7) rotated 90° about z (cam_from_world: q = (cos 45°, 0, 0, sin 45°),
// t = (1, 2, 3)), two 2D points of which the first sees 3D point 5.
struct TinyModel {
  std::string cameras = "# comment\n1 SIMPLE_PINHOLE 100 80 50 50 40\n";
  std::string images =
      "# IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "7 0.70710678118654757 0 0 0.70710678118654757 1 2 3 1 my image.png\n"
      "10 20 5 30 40 -1\n";
  std::string points = "5 1.5 2.5 3.5 255 0 10 0.5 7 0\n";

  std::filesystem::path Write(const std::filesystem::path& dir) const {
    WriteText(dir / "cameras.txt", cameras);
    WriteText(dir / "images.txt", images);
    WriteText(dir / "points3D.txt", points);
    return dir;
  }
};

TEST(Colmap, ReadsTheDocumentedConventions) {
  const auto dir = TinyModel().Write(test::TempDir() / "m");
  const SfmReconstruction r = ReadColmapModel(dir);
  ASSERT_EQ(r.intrinsics.size(), 1u);
  EXPECT_EQ(r.intrinsics[0].model, "SIMPLE_PINHOLE");
  EXPECT_EQ(r.intrinsics[0].params, (std::vector<double>{50, 50, 40}));
  EXPECT_EQ(r.intrinsics[0].width_px, 100);
  ASSERT_EQ(r.views.size(), 1u);
  EXPECT_EQ(r.views[0].id, 7);
  EXPECT_EQ(r.views[0].name, "my image.png");
  EXPECT_EQ(r.views[0].intrinsics_id, 1);
  // cam_from_world = (R = Rz(90°), t): the centre is −Rᵀt = −Rz(−90°)(1, 2, 3) = (−2, 1, −3); the camera's
  // x axis in the world is row 0 of R, (0, −1, 0).
  EXPECT_LT((r.views[0].center_world() - Eigen::Vector3d(-2, 1, -3)).norm(), 1e-12);
  EXPECT_LT((r.views[0].world_from_cam.linear().col(0) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
  ASSERT_EQ(r.num_points(), 1u);
  EXPECT_EQ(r.point_ids[0], 5);
  EXPECT_EQ(r.points_world[0], Eigen::Vector3d(1.5, 2.5, 3.5));
  EXPECT_EQ(r.point_colors_rgb[0], (std::array<std::uint8_t, 3>{255, 0, 10}));
  EXPECT_TRUE(r.point_labels.empty());
  ASSERT_EQ(r.observations.size(), 1u);  // the 2D point without 3D point is not an observation
  EXPECT_EQ(r.observations[0].point, 0u);
  EXPECT_EQ(r.observations[0].view, 0u);
  EXPECT_EQ(r.observations[0].pixel_px, Eigen::Vector2d(10, 20));
}

TEST(Colmap, TextAndBinaryRoundTrip) {
  const SfmReconstruction scene = test::SmallStreet();
  ASSERT_GT(scene.observations.size(), scene.num_points());  // points seen by several views
  for (ColmapEncoding encoding : {ColmapEncoding::kText, ColmapEncoding::kBinary}) {
    const auto dir = test::TempDir() / (encoding == ColmapEncoding::kText ? "text" : "bin");
    WriteColmapModel(dir, scene, encoding);
    const SfmReconstruction back = ReadColmapModel(dir);  // detects the encoding
    EXPECT_TRUE(
        std::filesystem::exists(dir / (encoding == ColmapEncoding::kText ? "images.txt" : "images.bin")));
    // The quaternion conversion rounds the rotation in the last bits.
    test::ExpectSameScene(scene, back, 1e-12);
    ASSERT_EQ(back.intrinsics.size(), 1u);
    EXPECT_EQ(back.intrinsics[0].model, scene.intrinsics[0].model);
    EXPECT_EQ(back.intrinsics[0].params, scene.intrinsics[0].params);
  }
}

TEST(Colmap, LabelsLiveInTheirOwnFile) {
  SfmReconstruction scene = test::SmallStreet();
  const auto dir = test::TempDir() / "m";
  WriteColmapModel(dir, scene);
  ASSERT_TRUE(std::filesystem::exists(dir / "points3D_labels.txt"));
  EXPECT_EQ(ReadColmapModel(dir).point_labels, scene.point_labels);
  // Without labels the file goes (a stale one would label other points).
  scene.point_labels.clear();
  WriteColmapModel(dir, scene);
  EXPECT_FALSE(std::filesystem::exists(dir / "points3D_labels.txt"));
  EXPECT_TRUE(ReadColmapModel(dir).point_labels.empty());
}

TEST(Colmap, BadLabelFiles) {
  const auto dir = TinyModel().Write(test::TempDir() / "m");
  WriteText(dir / "points3D_labels.txt", "6 3\n");
  ExpectReadError([&] { ReadColmapModel(dir); },
                  {"points3D_labels.txt", "line 1", "POINT3D_ID", "3D point 6 does not exist"});
  WriteText(dir / "points3D_labels.txt", "# nothing\n");
  ExpectReadError([&] { ReadColmapModel(dir); }, {"points3D_labels.txt", "point 5 has no label"});
  WriteText(dir / "points3D_labels.txt", "5 300\n");
  ExpectReadError([&] { ReadColmapModel(dir); }, {"LABEL", "'300'"});
}

// Each case: which file to change, its new text, and what the error must name.
struct BadText {
  const char* name;
  std::function<void(TinyModel*)> change;
  std::vector<std::string> expected;
};

TEST(Colmap, BadTextInputIsAClearError) {
  const std::vector<BadText> cases = {
      {"unknown model",
       [](TinyModel* m) { m->cameras = "1 PINHOLY 100 80 50 50 40\n"; },
       {"cameras.txt", "line 1 (CAMERA_ID 1)", "MODEL", "PINHOLY"}},
      {"parameter count",
       [](TinyModel* m) { m->cameras = "1 PINHOLE 100 80 50 50 40\n"; },
       {"cameras.txt", "PARAMS", "PINHOLE has 4 parameters (got 3)"}},
      {"negative size",
       [](TinyModel* m) { m->cameras = "1 SIMPLE_PINHOLE -100 80 50 50 40\n"; },
       {"cameras.txt", "line 1 (CAMERA_ID 1)", "WIDTH HEIGHT", "must not be negative"}},
      {"missing fields",
       [](TinyModel* m) { m->cameras = "1 SIMPLE_PINHOLE\n"; },
       {"cameras.txt", "line 1", "4 values, got 2"}},
      {"duplicate camera",
       [](TinyModel* m) { m->cameras += "1 SIMPLE_PINHOLE 100 80 50 50 40\n"; },
       {"cameras.txt", "camera id 1 appears twice"}},
      {"not a number",
       [](TinyModel* m) { m->points = "5 1.5 abc 3.5 255 0 10 0.5 7 0\n"; },
       {"points3D.txt", "line 1 (POINT3D_ID 5)", "X Y Z", "'abc' is not a number"}},
      {"NaN position",
       [](TinyModel* m) { m->points = "5 1.5 nan 3.5 255 0 10 0.5 7 0\n"; },
       {"points3D.txt", "POINT3D_ID 5", "X Y Z", "must be finite"}},
      {"infinite translation",
       [](TinyModel* m) {
         m->images = "7 0.70710678118654757 0 0 0.70710678118654757 1 inf 3 1 a.png\n10 20 5\n";
       },
       {"images.txt", "line 1 (IMAGE_ID 7)", "TX TY TZ", "must be finite"}},
      {"not a unit quaternion",
       [](TinyModel* m) { m->images = "7 1 1 0 0 1 2 3 1 a.png\n10 20 5\n"; },
       {"images.txt", "IMAGE_ID 7", "QW QX QY QZ", "not a unit quaternion (norm 1.414"}},
      {"unknown camera",
       [](TinyModel* m) { m->images = "7 1 0 0 0 1 2 3 9 a.png\n10 20 5\n"; },
       {"images.txt", "IMAGE_ID 7", "CAMERA_ID", "camera 9 does not exist"}},
      {"2D point of an unknown 3D point",
       [](TinyModel* m) { m->images = "7 1 0 0 0 1 2 3 1 a.png\n10 20 5 30 40 8\n"; },
       {"images.txt", "IMAGE_ID 7", "POINTS2D[1].POINT3D_ID", "3D point 8 does not exist"}},
      {"broken 2D point triples",
       [](TinyModel* m) { m->images = "7 1 0 0 0 1 2 3 1 a.png\n10 20 5 30\n"; },
       {"images.txt", "line 2 (POINTS2D of IMAGE_ID 7)", "triples"}},
      {"track of an unknown image",
       [](TinyModel* m) { m->points = "5 1.5 2.5 3.5 255 0 10 0.5 8 0\n"; },
       {"points3D.txt", "POINT3D_ID 5", "TRACK[0].IMAGE_ID", "image 8 does not exist"}},
      {"track beyond the 2D points",
       [](TinyModel* m) { m->points = "5 1.5 2.5 3.5 255 0 10 0.5 7 2\n"; },
       {"points3D.txt", "TRACK[0].POINT2D_IDX", "2 is beyond the 2 2D points of image 7"}},
      {"track and 2D point disagree",
       [](TinyModel* m) { m->points = "5 1.5 2.5 3.5 255 0 10 0.5 7 0 7 1\n"; },
       {"points3D.txt", "TRACK[1].POINT2D_IDX", "2D point 1 of image 7 has no 3D point in images.txt"}},
      {"odd track",
       [](TinyModel* m) { m->points = "5 1.5 2.5 3.5 255 0 10 0.5 7\n"; },
       {"points3D.txt", "TRACK", "pairs"}},
      {"colour out of range",
       [](TinyModel* m) { m->points = "5 1.5 2.5 3.5 256 0 10 0.5 7 0\n"; },
       {"points3D.txt", "R G B", "'256'"}},
      {"duplicate point",
       [](TinyModel* m) { m->points += "5 1 1 1 0 0 0 0\n"; },
       {"points3D.txt", "3D point id 5 appears twice"}},
  };
  for (const BadText& c : cases) {
    SCOPED_TRACE(c.name);
    TinyModel m;
    c.change(&m);
    const auto dir = m.Write(test::TempDir() / "m");
    try {
      ReadColmapModel(dir);
      ADD_FAILURE() << "no error";
    } catch (const ParseError& e) {
      const std::string what = e.what();
      for (const auto& part : c.expected)
        EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
    }
  }
}

TEST(Colmap, MissingFilesAndFolders) {
  const auto dir = test::TempDir();
  ExpectReadError([&] { ReadColmapModel(dir / "nowhere"); }, {"nowhere", "COLMAP model folder not found"});
  TinyModel().Write(dir / "m");
  std::filesystem::remove(dir / "m" / "points3D.txt");
  ExpectReadError([&] { ReadColmapModel(dir / "m"); }, {"points3D.txt", "file not found"});
}

TEST(Colmap, TruncatedOrCorruptBinaryIsAClearError) {
  const SfmReconstruction scene = test::SmallStreet();
  const auto dir = test::TempDir() / "bin";
  WriteColmapModel(dir, scene, ColmapEncoding::kBinary);
  const auto points = dir / "points3D.bin";
  const auto size = std::filesystem::file_size(points);
  std::filesystem::resize_file(points, size - 5);
  ExpectReadError([&] { ReadColmapModel(dir); }, {"points3D.bin", "point #", "TRACK", "truncated"});

  WriteColmapModel(dir, scene, ColmapEncoding::kBinary);
  {
    std::fstream f(dir / "images.bin", std::ios::in | std::ios::out | std::ios::binary);
    const std::uint64_t huge = 1ull << 60;
    f.write(reinterpret_cast<const char*>(&huge), sizeof(huge));
  }
  ExpectReadError([&] { ReadColmapModel(dir); }, {"images.bin", "number of images", "do not fit"});

  WriteColmapModel(dir, scene, ColmapEncoding::kBinary);
  {
    std::ofstream f(dir / "cameras.bin", std::ios::app | std::ios::binary);
    f << "xx";
  }
  ExpectReadError([&] { ReadColmapModel(dir); }, {"cameras.bin", "2 bytes after the last entry"});

  WriteColmapModel(dir, scene, ColmapEncoding::kBinary);
  {
    // The first point's X: bytes 8 + 8 .. 8 + 16 of points3D.bin.
    std::fstream f(dir / "points3D.bin", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(16);
    const double nan = std::nan("");
    f.write(reinterpret_cast<const char*>(&nan), sizeof(nan));
  }
  ExpectReadError([&] { ReadColmapModel(dir); },
                  {"points3D.bin", "point #0 (POINT3D_ID 1)", "X Y Z", "must be finite"});
}

TEST(Colmap, WriterRefusesWhatTheFormatCannotHold) {
  const auto dir = test::TempDir() / "m";
  SfmReconstruction scene = test::SmallStreet();
  scene.observations[0].pixel_px = Eigen::Vector2d::Constant(std::nan(""));
  EXPECT_THROW(WriteColmapModel(dir, scene), std::invalid_argument);
  scene = test::SmallStreet();
  scene.intrinsics[0] = {1, "fisheye", 100, 80, {1, 2, 3, 4, 5, 6, 7}};
  EXPECT_THROW(WriteColmapModel(dir, scene), std::invalid_argument);
  // OpenMVG's pinhole is COLMAP's SIMPLE_PINHOLE.
  scene.intrinsics[0] = {1, "pinhole", 100, 80, {50, 50, 40}};
  WriteColmapModel(dir, scene);
  EXPECT_EQ(ReadColmapModel(dir).intrinsics[0].model, "SIMPLE_PINHOLE");
}

}  // namespace
}  // namespace semap::io
