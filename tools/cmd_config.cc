// `semap config`: print the effective configuration, or the defaults with their documentation.
#include <iostream>

#include "tools/cli_common.h"

namespace semap::tools {

void RegisterConfigCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand("config", "Print the effective configuration (defaults, --config, --set)");
  auto args = std::make_shared<CommonArgs>();
  auto defaults = std::make_shared<bool>(false);
  AddCommonOptions(cmd, args.get());
  cmd->add_flag("--defaults", *defaults, "print the built-in defaults (this is config/default.yaml)");
  cmd->callback([=]() {
    *exit_code = RunGuarded(*args, [&]() {
      const app::Config config = *defaults ? app::Config{} : LoadConfigFrom(*args);
      std::cout << app::DumpConfig(config);
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
