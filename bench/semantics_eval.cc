// semap_semantics_eval: ENet Cityscapes on the 20 real KITTI stereo-2015 frames: time per frame on one core,
// the share of pixels per class, a geometric plausibility check of the ground classes against the Velodyne
// (LiDAR returns near the ground plane under the camera vs those well above it) and an overlay image.
//
// Usage: semap_semantics_eval [--data DIR] [--model FILE] [--overlay OUT.png] [--overlay-index K] [--stretch]
// [--threads N]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "tests/common/kitti2015_subset.h"

int main(int argc, char** argv) {
  CLI::App app{"ENet on the KITTI stereo-2015 subset: time per frame, class shares, ground check, overlay"};
  const std::string shared = SEMAP_SHARED_DIR;
  std::string data = shared + "/data/kitti_stereo2015_subset";
  std::string model = shared + "/models/enet-cityscapes/enet-model.net";
  std::string overlay_path;
  size_t overlay_index = 0;
  bool stretch = false;
  int threads = 1;
  // KITTI camera height above the road: ~1.65 m. A LiDAR return with camera-frame y within this band of it
  // counts as "ground height"; one more than kAboveGround_m above it as "clearly not ground".
  double ground_band_m = 0.3;
  double above_ground_m = 1.0;
  double camera_height_m = 1.65;
  app.add_option("--data", data, "kitti_stereo2015_subset folder");
  app.add_option("--model", model, "ENet model");
  app.add_option("--overlay", overlay_path, "write the overlay of the first frame here (PNG)");
  app.add_option("--overlay-index", overlay_index, "frame (0-based, in name order) whose overlay is written");
  app.add_flag("--stretch", stretch, "stretch the image to the network input instead of keeping its aspect");
  app.add_option("--threads", threads, "OpenCV threads");
  std::string head = "fused";
  app.add_option(
         "--head", head,
         "ENet's last layer: fused (computed on the image's rows with the argmax, the default) or network "
         "(OpenCV's, over the whole output)")
      ->check(CLI::IsMember({"fused", "network"}));
  CLI11_PARSE(app, argc, argv);
  try {
    cv::setNumThreads(threads);
    semap::SemanticsOptions o;
    o.source = semap::LabelSource::kEnet;
    o.enet_model_path = model;
    o.enet_keep_aspect = !stretch;
    auto segmenter = std::make_unique<semap::EnetSegmenter>(
        o, head == "network" ? semap::EnetHead::kNetwork : semap::EnetHead::kFused);
    const semap::ClassMap& classes = segmenter->class_map();
    std::vector<double> share(20, 0.0);
    double seconds = 0.0, cpu_seconds = 0.0, total_px = 0.0;
    size_t ground_height = 0, ground_height_labelled_ground = 0, high = 0, high_labelled_ground = 0;
    const auto names = semap::test::ListStereo2015Frames(data);
    for (size_t k = 0; k < names.size(); ++k) {
      const auto f = semap::test::LoadStereo2015Frame(data, names[k]);
      if (k == 0) segmenter->Segment(f.frame.left);  // warm-up: network buffers
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      const cv::Mat labels = segmenter->Segment(f.frame.left);
      cpu_seconds += double(std::clock() - c0) / CLOCKS_PER_SEC;
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (auto it = labels.begin<semap::Label>(); it != labels.end<semap::Label>(); ++it) {
        if (*it < share.size()) share[*it] += 1.0;
      }
      total_px += static_cast<double>(labels.total());
      if (k == overlay_index && !overlay_path.empty()) {
        cv::imwrite(overlay_path, semap::OverlayLabels(f.frame.left, labels, classes, 0.5));
      }
      for (const auto& p : f.frame.velodyne->points_velo) {
        const Eigen::Vector3d c = f.frame.velodyne->cam_from_velo * p.head<3>().cast<double>();
        if (c.z() <= 1.0 || c.z() > 40.0) continue;
        const Eigen::Vector2d uv = f.frame.calibration.Project(c);
        if (!f.frame.calibration.InImage(uv)) continue;
        const bool is_ground =
            classes.Role(labels.at<semap::Label>(int(uv.y()), int(uv.x()))) == semap::ClassRole::kGround;
        if (std::abs(c.y() - camera_height_m) < ground_band_m) {
          ++ground_height;
          ground_height_labelled_ground += is_ground;
        } else if (c.y() < camera_height_m - above_ground_m) {
          ++high;
          high_labelled_ground += is_ground;
        }
      }
    }
    const double n = static_cast<double>(names.size());
    std::printf(
        "ENet (%s, %s head) on %zu frames, OpenCV threads %d: %.1f ms/frame wall, %.1f ms/frame CPU\n",
        stretch ? "stretched" : "aspect kept",
        segmenter->head() == semap::EnetHead::kFused ? "fused" : "network", names.size(), cv::getNumThreads(),
        1000.0 * seconds / n, 1000.0 * cpu_seconds / n);
    std::printf("pixel shares:");
    for (size_t c = 0; c < share.size(); ++c) {
      if (share[c] / total_px >= 0.005) {
        std::printf(" %s %.1f%%", classes.Get(static_cast<semap::Label>(c)).name.c_str(),
                    100.0 * share[c] / total_px);
      }
    }
    std::printf("\nLiDAR returns at road height (|y - %.2f| < %.1f m) labelled ground: %.1f %% of %zu\n",
                camera_height_m, ground_band_m, 100.0 * ground_height_labelled_ground / ground_height,
                ground_height);
    std::printf("LiDAR returns > %.1f m above the road labelled ground: %.1f %% of %zu\n", above_ground_m,
                100.0 * high_labelled_ground / high, high);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_semantics_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
