// The Strecha multi-view layout: a hand-written camera, and every kind of bad input naming its file and line.
#include "io/sfm/strecha.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <string>

#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_test_util.h"

namespace semap::io {
namespace {

using test::ExpectReadError;
using test::WriteText;

// K with f = 1000 px and the centre (320, 240); R (camera to world) a quarter turn about y, so the camera
// looks along world +x; C = (1, 2, 3); a 640 × 480 image.
struct Camera {
  std::vector<std::string> lines{"1000 0 320", "0 1000 240", "0 0 1", "0 0 0",  "0 0 1",
                                 "0 1 0",      "-1 0 0",     "1 2 3", "640 480"};
  std::string Text() const {
    std::string text;
    for (const auto& line : lines) text += line + "\n";
    return text;
  }
};

// A set with one image (0000.png, 640 × 480) and its camera; returns the root.
std::filesystem::path WriteSet(const Camera& camera, cv::Size image_size = cv::Size(640, 480)) {
  const auto root = test::TempDir() / "strecha";
  std::filesystem::create_directories(root / "images");
  cv::imwrite((root / "images" / "0000.png").string(), cv::Mat(image_size, CV_8UC1, cv::Scalar(90)));
  WriteText(root / "images" / "K.txt", "1000 0 320\n0 1000 240\n0 0 1\n");
  WriteText(root / "gt_dense_cameras" / "0000.png.camera", camera.Text());
  return root;
}

TEST(Strecha, ReadsTheDocumentedConventions) {
  const auto root = WriteSet(Camera{});
  const std::vector<StrechaView> views = ReadStrechaSet(root);
  ASSERT_EQ(views.size(), 1u);
  const StrechaView& v = views[0];
  EXPECT_EQ(v.image, root / "images" / "0000.png");
  EXPECT_EQ(v.camera_file, root / "gt_dense_cameras" / "0000.png.camera");
  EXPECT_EQ(v.width_px, 640);
  EXPECT_EQ(v.height_px, 480);
  Eigen::Matrix3d K;
  K << 1000, 0, 320, 0, 1000, 240, 0, 0, 1;
  EXPECT_EQ(v.K, K);
  // world_from_cam: rotation R, translation C; the optical axis is world +x.
  EXPECT_LT((v.world_from_cam.translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  EXPECT_LT((v.world_from_cam.linear().col(2) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  // x ~ K Rᵀ (X − C): X = C + R (0.5, −0.2, 4) = (5, 1.8, 2.5) is seen at (320 + 125, 240 − 50), depth 4.
  const Eigen::Vector3d x_cam = v.world_from_cam.inverse(Eigen::Isometry) * Eigen::Vector3d(5, 1.8, 2.5);
  const Eigen::Vector3d x = v.K * x_cam;
  EXPECT_NEAR(x_cam.z(), 4.0, 1e-12);
  EXPECT_NEAR(x.x() / x.z(), 445.0, 1e-9);
  EXPECT_NEAR(x.y() / x.z(), 190.0, 1e-9);
}

TEST(Strecha, MalformedCamerasNameTheFileAndLine) {
  struct Case {
    const char* name;
    int line;  // 1-based line to replace (0: drop the last line)
    std::string text;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"not a number", 2, "0 abc 240", {"line 2", "K row 2", "'abc' is not a number"}},
      {"too few values", 8, "1 2", {"line 8", "C", "expects 3 numbers, got 2"}},
      {"too many values", 9, "640 480 3", {"line 9", "expects 2 numbers, got 3"}},
      {"truncated", 0, "", {"line 9", "missing"}},
      {"not orthonormal", 5, "0 0 2", {"lines 5-7", "R", "orthonormal"}},
      {"a reflection", 7, "1 0 0", {"lines 5-7", "R", "determinant"}},
      {"distortion", 4, "0.1 0 0", {"line 4", "distortion"}},
      {"K not pinhole", 3, "0 1 1", {"lines 1-3", "K"}},
      {"size not integers", 9, "640.5 480", {"line 9", "positive integers"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Camera camera;
    if (c.line == 0) {
      camera.lines.pop_back();
    } else {
      camera.lines[static_cast<size_t>(c.line - 1)] = c.text;
    }
    const auto root = WriteSet(camera);
    std::vector<std::string> parts = c.expected;
    parts.push_back("0000.png.camera");
    try {
      ReadStrechaSet(root);
      ADD_FAILURE() << "no error";
    } catch (const ParseError& e) {
      for (const auto& part : parts)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
            << "'" << part << "' not in: " << e.what();
    }
  }
}

TEST(Strecha, ImageSizeMustMatchLine9) {
  const auto root = WriteSet(Camera{}, cv::Size(320, 240));
  ExpectReadError([&] { ReadStrechaSet(root); },
                  {"0000.png.camera", "line 9", "says 640x480, but 0000.png is 320x240"});
}

TEST(Strecha, MissingCameraOrFolderIsAFileError) {
  const auto root = WriteSet(Camera{});
  cv::imwrite((root / "images" / "0001.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)));
  ExpectReadError([&] { ReadStrechaSet(root); }, {"0001.png.camera", "missing", "0001.png"});
  std::filesystem::remove_all(root / "gt_dense_cameras");
  ExpectReadError([&] { ReadStrechaSet(root); }, {"gt_dense_cameras", "not a folder"});
  ExpectReadError([&] { ReadStrechaCamera(root / "nowhere.camera"); }, {"nowhere.camera", "cannot be read"});
}

}  // namespace
}  // namespace semap::io
