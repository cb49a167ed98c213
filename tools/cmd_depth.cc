// `semap depth PATH --frame N --out DIR`: run the depth stage (and the labelling rule) on one frame and write
// the disparity (KITTI uint16 PNG), a false-colour disparity PNG and the labelled point cloud (PLY).
// `semap depth PATH --all --out DIR`: the same depth stage as `semap run` on every selected frame, written as
// depth maps with the poses and intrinsics, for other fusion tools (bench/tsdf_compare.sh).
#include "app/depth/depth_maps.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterDepthCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    int frame = 0;
    std::string out;
    std::string colour = "image";
    bool ascii = false;
    bool all = false;
    int frames = 0;
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
  cmd->add_flag(
      "--all", args->all,
      "every selected frame (input.first_frame, --frames) through the depth stage of `semap run`, densely "
      "(no point budget): OUT/depth/NNNNNN.png (16-bit depth in mm, 0 = none), OUT/poses.txt, "
      "OUT/camera.txt, for other fusion tools");
  cmd->add_option("--frames", args->frames, "with --all: frames to write, 0 = all (input.max_frames)")
      ->check(FrameCountCheck());
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      app::Config config = LoadConfigFrom(args->common);
      if (args->all) {
        if (args->frames > 0) config.input.max_frames = args->frames;
        app::WriteAllDepthMaps(config, args->path, args->out);
        return kExitOk;
      }
      app::WriteFrameDepth(config,
                           {args->path, args->frame, args->out, args->colour == "label", args->ascii});
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
