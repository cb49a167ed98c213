// semap_synth_label_eval: label accuracy of the depth stage's points on a generated sequence (`semap synth`,
// KITTI raw layout with exact labels semantic/data and exact depth depth/data of image_02).
//
// For every frame: SGBM points (default depth options), labelled by the first-camera rule with (a) the exact
// label PNG and (b) ENet; each point is reprojected into its first camera through world_from_cam (identity
// here: points stay in the camera frame) and its label compared with the exact label at that pixel. Points
// whose depth is within 5 % of the exact depth lie on the surface that pixel sees: accuracy is reported over
// those and over all points.
//
// Usage: semap_synth_label_eval DRIVE_DIR [--frames N] [--no-enet]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "engine/depth/stereo_depth.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "tests/common/kitti2015_subset.h"

namespace {

struct Tally {
  size_t points = 0, correct = 0, on_surface = 0, on_surface_correct = 0;
  size_t ground_wall_other_correct = 0;  // agreement on the simplifier's roles only (ground / wall / keep)
  void Print(const char* title) const {
    std::printf(
        "%-22s all points %6.2f %% of %zu | on the exact surface %6.2f %% of %zu | role (ground/wall/"
        "keep) %6.2f %%\n",
        title, 100.0 * correct / points, points, 100.0 * on_surface_correct / on_surface, on_surface,
        100.0 * ground_wall_other_correct / points);
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Label accuracy of projected points on a generated sequence (exact labels and depth)"};
  std::string drive;
  int max_frames = 10;
  bool no_enet = false;
  std::string model = std::string(SEMAP_SHARED_DIR) + "/models/enet-cityscapes/enet-model.net";
  double surface_tolerance = 0.05;
  app.add_option("DRIVE_DIR", drive, "generated drive folder (…/DATE/DATE_drive_0001_sync)")->required();
  app.add_option("--frames", max_frames, "frames to evaluate");
  app.add_flag("--no-enet", no_enet, "skip ENet");
  app.add_option("--model", model, "ENet model");
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fs = std::filesystem;
    const fs::path dir(drive);
    semap::StereoCalibration calib;
    semap::Pose3d cam_from_velo;
    semap::test::ReadStereo2015Calibration(dir.parent_path(), &calib, &cam_from_velo);
    const semap::ClassMap classes = semap::ClassMap::Cityscapes();
    const semap::StereoDepth depth{semap::DepthOptions{}};
    std::unique_ptr<semap::Segmenter> enet;
    if (!no_enet) {
      semap::SemanticsOptions o;
      o.source = semap::LabelSource::kEnet;
      o.enet_model_path = model;
      enet = semap::MakeSegmenter(o);
    }
    Tally exact_tally, enet_tally;
    size_t enet_pixels = 0, enet_pixels_correct = 0;
    for (int k = 0; k < max_frames; ++k) {
      char name[32];
      std::snprintf(name, sizeof(name), "%010d.png", k);
      semap::Frame f;
      f.id = k;
      f.left = cv::imread((dir / "image_02" / "data" / name).string(), cv::IMREAD_COLOR);
      f.right = cv::imread((dir / "image_03" / "data" / name).string(), cv::IMREAD_COLOR);
      if (f.left.empty()) break;
      const cv::Mat exact_labels =
          cv::imread((dir / "semantic" / "data" / name).string(), cv::IMREAD_UNCHANGED);
      const cv::Mat exact_depth_mm =
          cv::imread((dir / "depth" / "data" / name).string(), cv::IMREAD_UNCHANGED);
      if (exact_labels.type() != CV_8UC1 || exact_depth_mm.type() != CV_16UC1) {
        throw std::runtime_error(std::string("bad exact labels or depth for ") + name);
      }
      f.calibration = calib;
      f.calibration.width_px = f.left.cols;
      f.calibration.height_px = f.left.rows;
      const semap::LabelledCloud base = depth.Process(f);
      auto evaluate = [&](const cv::Mat& labels, Tally* t) {
        semap::LabelledCloud cloud = base;
        semap::ApplyFirstCameraLabels(cloud, f.id, labels, f.left.size(), classes.unlabelled_id());
        for (size_t i = 0; i < cloud.size(); ++i) {
          // Reproject the point into its first camera (world = camera frame here).
          const Eigen::Vector3d& p = cloud.positions_world[i];
          const Eigen::Vector2d uv = f.calibration.Project(p);
          const int u = static_cast<int>(std::lround(uv.x()));
          const int v = static_cast<int>(std::lround(uv.y()));
          if (u < 0 || v < 0 || u >= f.left.cols || v >= f.left.rows) continue;
          const semap::Label truth = exact_labels.at<semap::Label>(v, u);
          const bool ok = cloud.labels[i] == truth;
          ++t->points;
          t->correct += ok;
          t->ground_wall_other_correct += classes.Role(cloud.labels[i]) == classes.Role(truth);
          const double z_exact = exact_depth_mm.at<std::uint16_t>(v, u) / 1000.0;
          if (z_exact > 0.0 && std::abs(p.z() - z_exact) <= surface_tolerance * z_exact) {
            ++t->on_surface;
            t->on_surface_correct += ok;
          }
        }
      };
      evaluate(exact_labels, &exact_tally);
      if (enet) {
        const cv::Mat enet_labels = enet->Segment(f.left);
        evaluate(enet_labels, &enet_tally);
        enet_pixels += enet_labels.total();
        enet_pixels_correct += static_cast<size_t>(cv::countNonZero(enet_labels == exact_labels));
      }
    }
    std::printf("%s: %zu points evaluated\n", drive.c_str(), exact_tally.points);
    exact_tally.Print("exact label PNGs");
    if (enet) {
      enet_tally.Print("ENet");
      std::printf("ENet pixel accuracy on the generated images: %.2f %%\n",
                  100.0 * enet_pixels_correct / enet_pixels);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_synth_label_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
