// `semap segment PATH --frame N --out DIR`: run the built-in segmenter (ENet Cityscapes) on one frame and
// write the label PNG (class ids) and a colour overlay.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "io/image/image_files.h"
#include "tools/cli_common.h"
#include "app/depth/frame_at.h"

namespace semap::tools {

void RegisterSegmentCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    int frame = 0;
    std::string out;
    double alpha = 0.5;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("segment",
                                 "Segment one frame with the built-in ENet Cityscapes model: label PNG "
                                 "and colour overlay");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path, "dataset folder (KITTI raw, odometry, stereo-2015 or generated)")
      ->required();
  cmd->add_option("--frame", args->frame, "frame number as on disk (e.g. 57 for 000057_10.png)");
  cmd->add_option("--out", args->out, "output folder (created)")->required();
  cmd->add_option("--alpha", args->alpha, "weight of the label colours in the overlay")
      ->check(CLI::Range(0.0, 1.0));
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const app::Config config = LoadConfigFrom(args->common);
      io::FrameSourceOptions input = config.input;
      input.load_velodyne = false;
      const app::FrameAt at = app::ReadFrameAt(args->path, args->frame, input);
      SemanticsOptions semantics = config.semantics;
      semantics.source = LabelSource::kEnet;  // this command always runs the built-in segmenter
      auto segmenter = MakeSegmenter(semantics);
      const auto t0 = std::chrono::steady_clock::now();
      const cv::Mat labels = segmenter->Segment(at.frame.left);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

      const std::filesystem::path out(args->out);
      std::filesystem::create_directories(out);
      char stem[64];
      std::snprintf(stem, sizeof(stem), "%06lld", static_cast<long long>(at.frame.id));
      const auto labels_png = out / (std::string("labels_") + stem + ".png");
      const auto overlay_png = out / (std::string("overlay_") + stem + ".png");
      io::WritePng(labels_png, labels);
      io::WritePng(overlay_png, OverlayLabels(at.frame.left, labels, segmenter->class_map(), args->alpha));

      const ClassMap& classes = segmenter->class_map();
      std::printf("frame %lld: %s in %.3f s; classes:", static_cast<long long>(at.frame.id),
                  segmenter->name().c_str(), seconds);
      for (const auto& c : classes.classes()) {
        const int n = cv::countNonZero(labels == c.id);
        if (n > 0) std::printf(" %s %.1f%%", c.name.c_str(), 100.0 * n / static_cast<double>(labels.total()));
      }
      std::printf("\nwrote %s\n      %s\n", labels_png.c_str(), overlay_png.c_str());
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
