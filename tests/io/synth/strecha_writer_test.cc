#include "io/synth/strecha_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "engine/eval/surface_metrics.h"
#include "io/frame_source.h"
#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"
#include "io/sfm/strecha.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// Three views at a quarter of the default image size (the same field of view).
sim::MultiViewSetOptions ThreeSmallViews() {
  sim::MultiViewSetOptions o;
  o.num_views = 3;
  o.ScaleImage(0.25);
  return o;
}

sim::SynthOptions Seed(std::uint64_t seed) {
  sim::SynthOptions o;
  o.seed = seed;
  return o;
}

TEST(StrechaWriter, TheReaderReadsBackTheCamerasAndTheImagesAsRendered) {
  const sim::MultiViewSet set(Seed(7), ThreeSmallViews());
  const fs::path root = test::TempDir() / "set";
  const StrechaWriteSummary summary = WriteSyntheticStrecha(set, root);
  EXPECT_EQ(summary.num_views, 3);
  EXPECT_EQ(summary.label_pixels.total(), 3u * 192u * 128u);
  EXPECT_TRUE(fs::is_regular_file(root / "images" / "K.txt"));
  EXPECT_TRUE(IsStrechaSet(root));

  const std::vector<StrechaView> views = ReadStrechaSet(root);  // K.txt is not a view
  ASSERT_EQ(views.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE("view " + std::to_string(i));
    const sim::MultiViewCamera& truth = set.camera(i);
    const StrechaView& v = views[static_cast<size_t>(i)];
    EXPECT_EQ(v.image, root / "images" / (StrechaViewStem(i) + ".png"));
    // %.17g text: exactly the doubles written.
    EXPECT_EQ(v.K, truth.K);
    EXPECT_EQ(v.world_from_cam.matrix(), truth.world_from_cam.matrix());
    EXPECT_EQ(v.width_px, 192);
    EXPECT_EQ(v.height_px, 128);

    const sim::CameraImage rendered = set.Render(i);
    const std::string png = StrechaViewStem(i) + ".png";
    const cv::Mat colour = cv::imread((root / "images" / png).string(), cv::IMREAD_COLOR);
    EXPECT_EQ(cv::norm(colour, rendered.color, cv::NORM_INF), 0.0);
    const cv::Mat labels = cv::imread((root / "labels" / png).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(labels.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(labels, rendered.labels, cv::NORM_INF), 0.0);
    // Millimetres, rounded: within half a millimetre of the renderer's depth, and none where it has none.
    const cv::Mat depth = ReadDepthPngMm(root / "depth" / png);
    int with_depth = 0;
    for (int y = 0; y < depth.rows; ++y) {
      for (int x = 0; x < depth.cols; ++x) {
        const float z = rendered.depth_m.at<float>(y, x), read = depth.at<float>(y, x);
        if (z == 0.0f) {
          EXPECT_EQ(read, 0.0f);
          continue;
        }
        ++with_depth;
        ASSERT_NEAR(read, z, 0.5e-3 + 1e-6 * z) << x << ", " << y;
      }
    }
    EXPECT_GT(with_depth, 0.9 * depth.total());
  }
}

TEST(StrechaWriter, TheSetStreamsAsStrechaFramesWithLabels) {
  const sim::MultiViewSet set(Seed(8), ThreeSmallViews());
  const fs::path root = test::TempDir() / "set";
  WriteSyntheticStrecha(set, root);
  EXPECT_EQ(DetectLayout(root), DatasetLayout::kStrecha);
  FrameSourceOptions options;
  options.neighbour_views = 2;
  auto source = OpenFrameSource(root, options);
  EXPECT_TRUE(source->info().has_labels);
  EXPECT_EQ(source->info().label_files.size(), 3u);
  int frames = 0;
  while (const auto f = source->Next()) {
    SCOPED_TRACE("frame " + std::to_string(f->id));
    // The arc's ends are 90 degrees apart, beyond the 60 degrees of a neighbour: they see only the middle.
    EXPECT_EQ(f->neighbour_views.size(), f->id == 1 ? 2u : 1u);
    ASSERT_EQ(f->labels.size(), cv::Size(192, 128));
    EXPECT_EQ(cv::norm(f->labels, set.Render(static_cast<int>(f->id)).labels, cv::NORM_INF), 0.0);
    EXPECT_DOUBLE_EQ(f->calibration.fx_px, 172.5);
    ++frames;
  }
  EXPECT_EQ(frames, 3);
}

// Independently of the renderer: each depth pixel, unprojected through the camera read back, lies on the
// scene mesh read back.
TEST(StrechaWriter, EveryDepthPixelLiesOnTheSceneMesh) {
  const sim::MultiViewSet set(Seed(9), ThreeSmallViews());
  const fs::path root = test::TempDir() / "set";
  WriteSyntheticStrecha(set, root);
  const std::vector<StrechaView> views = ReadStrechaSet(root);
  const SurfaceDistance to_scene(ReadMeshPly(root / "scene_mesh.ply"));
  for (size_t i = 0; i < views.size(); ++i) {
    const StrechaView& v = views[i];
    const cv::Mat depth = ReadDepthPngMm(root / "depth" / (v.image.stem().string() + ".png"));
    int checked = 0;
    double worst_m = 0.0;
    for (int y = 0; y < depth.rows; y += 3) {
      for (int x = 0; x < depth.cols; x += 3) {
        const double z = depth.at<float>(y, x);
        if (z == 0.0) continue;
        const Eigen::Vector3d ray((x - v.K(0, 2)) / v.K(0, 0), (y - v.K(1, 2)) / v.K(1, 1), 1.0);
        worst_m = std::max(worst_m, to_scene(v.world_from_cam * (z * ray)));
        ++checked;
      }
    }
    EXPECT_GT(checked, 2000) << "view " << i;
    // The depth's rounding to 0.5 mm along z, stretched along the ray (|ray| < 1.2 in this field of view).
    EXPECT_LT(worst_m, 0.6e-3) << "view " << i;
  }
}

}  // namespace
}  // namespace semap::io
