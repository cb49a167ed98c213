// `semap depth PATH --frame N --out DIR`: run the depth stage (and the labelling rule) on one frame and write
// the disparity (KITTI uint16 PNG), a false-colour disparity PNG and the labelled point cloud (PLY).
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "engine/depth/stereo_depth.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"
#include "tools/frame_at.h"

namespace semap::tools {
namespace {

std::string Stem(const char* what, std::int64_t id) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%s_%06lld", what, static_cast<long long>(id));
  return buf;
}

}  // namespace

void RegisterDepthCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    int frame = 0;
    std::string out;
    std::string colour = "image";
    bool ascii = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("depth", "SGBM depth of one frame: disparity PNGs and the labelled point cloud");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path, "dataset folder (KITTI raw, odometry, stereo-2015 or generated)")
      ->required();
  cmd->add_option("--frame", args->frame, "frame number as on disk (e.g. 57 for 000057_10.png)");
  cmd->add_option("--out", args->out, "output folder (created)")->required();
  cmd->add_option("--colour,--color", args->colour, "point colours in the PLY: image or label")
      ->check(CLI::IsMember({"image", "label"}));
  cmd->add_flag("--ascii", args->ascii, "write ASCII PLY instead of binary");
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const io::Config config = LoadConfigFrom(args->common);
      io::FrameSourceOptions input = config.input;
      input.load_velodyne = false;
      const FrameAt at = ReadFrameAt(args->path, args->frame, input);
      const Frame& frame = at.frame;

      const auto t0 = std::chrono::steady_clock::now();
      const StereoDepth depth(config.depth);
      const DisparityResult disparity = depth.Compute(frame.left, frame.right);
      LabelledCloud cloud = depth.ToCloud(frame, disparity.disparity_px, disparity.confidence);
      const double depth_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

      auto segmenter = MakeSegmenter(config.semantics);
      const cv::Mat labels = FrameLabels(frame, config.semantics, segmenter.get());
      const ClassMap& classes = segmenter ? segmenter->class_map() : at.class_map;
      const LabellingReport report =
          ApplyFirstCameraLabels(cloud, frame.id, labels, frame.left.size(), classes.unlabelled_id(),
                                 config.semantics.size_mismatch);
      if (report.resized) {
        spdlog::warn("frame {}: label image {}x{} resized (nearest neighbour) to the image size {}x{}",
                     frame.id, labels.cols, labels.rows, frame.left.cols, frame.left.rows);
      }
      if (args->colour == "label") {
        for (size_t i = 0; i < cloud.size(); ++i) cloud.colors_rgb[i] = classes.Color(cloud.labels[i]);
      }

      const std::filesystem::path out(args->out);
      std::filesystem::create_directories(out);
      const auto disp_png = out / (Stem("disparity", frame.id) + ".png");
      const auto colour_png = out / (Stem("disparity_colour", frame.id) + ".png");
      const auto cloud_ply = out / (Stem("cloud", frame.id) + ".ply");
      io::WriteKittiDisparityPng(disp_png, disparity.disparity_px);
      io::WritePng(colour_png, io::FalseColourDisparity(disparity.disparity_px,
                                                        static_cast<float>(config.depth.num_disparities)));
      io::WriteCloudPly(cloud_ply, cloud,
                        args->ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);

      const int valid = cv::countNonZero(disparity.disparity_px > 0.0f);
      std::printf(
          "frame %lld: %dx%d, disparity on %.1f %% of the pixels, %zu points in [%.1f, %.1f] m, "
          "depth stage %.3f s\n",
          static_cast<long long>(frame.id), frame.left.cols, frame.left.rows,
          100.0 * valid / static_cast<double>(frame.left.total()), cloud.size(), config.depth.min_depth_m,
          config.depth.max_depth_m, depth_s);
      std::printf("labels: %s (%zu points labelled, %zu outside the label image)\n",
                  labels.empty() ? "none (all points unlabelled)" : LabelSourceName(config.semantics.source),
                  report.labelled, report.outside_image);
      std::printf("wrote %s\n      %s\n      %s\n", disp_png.c_str(), colour_png.c_str(), cloud_ply.c_str());
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
