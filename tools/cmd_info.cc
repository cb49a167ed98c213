// `semap info PATH`: what a dataset folder holds, as the frame sources will read it
// (app/dataset/dataset_info.h).
#include <memory>

#include "app/dataset/dataset_info.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterInfoCommand(CLI::App& app, int* exit_code) {
  auto* cmd =
      app.add_subcommand("info", "Describe a dataset folder: layout, frames, calibration, what it holds");
  auto args = std::make_shared<CommonArgs>();
  auto path = std::make_shared<std::string>();
  auto sample = std::make_shared<int>(20);
  AddCommonOptions(cmd, args.get());
  cmd->add_option("path", *path, "dataset folder (KITTI raw drive or date folder, odometry, stereo-2015)")
      ->required();
  cmd->add_option("--sample-frames", *sample, "label images read for the class composition (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([=]() {
    *exit_code = RunGuarded(*args, [&]() {
      app::PrintDatasetInfo(LoadConfigFrom(*args), *path, *sample);
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
