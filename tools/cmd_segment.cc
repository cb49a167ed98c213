// `semap segment PATH --frame N --out DIR`: run the built-in segmenter (ENet Cityscapes) on one frame and
// write the label PNG (class ids) and a colour overlay.
#include <memory>

#include "app/single/single_commands.h"
#include "tools/cli_common.h"

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
      app::SegmentFrame(config, {args->path, args->frame, args->out, args->alpha});
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
