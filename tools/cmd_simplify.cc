// `semap simplify CLOUD.ply --method PS --out OUT.ply`: simplify a labelled point cloud (labels in the PLY,
// ids of input.class_map, Cityscapes by default) and print per-class in/kept counts and the time.
#include <memory>

#include "app/single/single_commands.h"
#include "engine/simplify/simplify.h"
#include "tools/cli_common.h"

namespace semap::tools {

void RegisterSimplifyCommand(CLI::App& app, int* exit_code) {
  struct Args {
    CommonArgs common;
    std::string cloud;
    std::string out;
    std::string method;  // empty = simplify.method of the config
    bool ascii = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("simplify",
                                 "Simplify a labelled point cloud (PLY with a `label` property) with "
                                 "one of the paper's methods or a baseline");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("CLOUD", args->cloud,
                  "input point cloud (.ply, per-vertex label = class id of input.class_map)")
      ->required();
  cmd->add_option("--out", args->out, "output point cloud (.ply); omitted = statistics only");
  std::string names;
  for (auto m : AllSimplifyMethods()) names += std::string(names.empty() ? "" : ", ") + SimplifyMethodName(m);
  cmd->add_option("--method", args->method, "method (overrides simplify.method): " + names);
  cmd->add_flag("--ascii", args->ascii, "write ASCII PLY instead of binary");
  cmd->callback([=]() {
    *exit_code = RunGuarded(args->common, [&]() {
      app::Config config = LoadConfigFrom(args->common);
      if (!args->method.empty()) config.simplify.method = SimplifyMethodFromName(args->method);
      app::SimplifyCloudFile(config, {args->cloud, args->out, args->ascii});
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
