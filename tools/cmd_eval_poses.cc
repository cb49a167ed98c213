// `semap eval-poses SEQ --poses FILE`: an estimated trajectory (a run's poses_odometry.txt or .tum) against
// the sequence's own poses: the KITTI odometry metric, the relative error over 10-frame windows and the ATE.
#include <cstdio>

#include "app/eval/pose_evaluation.h"
#include "io/atomic_file.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterEvalPosesCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string path;
    std::string poses;
    std::string json;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("eval-poses",
                                 "An estimated camera trajectory against the sequence's poses: KITTI "
                                 "odometry metric (100-800 m), relative error over 10 frames, ATE");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("PATH", args->path,
                  "dataset folder with poses (the frames input.first_frame / max_frames select)")
      ->required();
  cmd->add_option("--poses", args->poses,
                  "the estimate: KITTI pose format (one line per frame) or TUM (.tum, matched by timestamp)")
      ->required();
  cmd->add_option("--json", args->json, "also write the figures as JSON to this file");
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      const app::Config config = LoadConfigFrom(args->common);
      const app::PoseEvaluation e = app::EvaluatePoses(config, args->path, args->poses);
      std::fputs(app::PoseEvaluationText(e).c_str(), stdout);
      if (!args->json.empty()) io::WriteFileAtomically(args->json, app::PoseEvaluationJson(e));
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
