// `semap simplify CLOUD.ply --method PS --out OUT.ply`: simplify a labelled point cloud (labels in the PLY,
// ids of input.class_map, Cityscapes by default) and print per-class in/kept counts and the time.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <iostream>

#include "engine/simplify/simplify.h"
#include "io/labels/class_map_yaml.h"
#include "io/mesh/ply_off.h"
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
      const ClassMap class_map = io::LoadClassMap(config.input.class_map);  // empty = Cityscapes
      const LabelledCloud cloud = io::ReadCloudPly(args->cloud);
      const SimplifyResult result = Simplify(cloud, class_map, config.simplify);

      std::printf("%s: %zu points, method %s\n", args->cloud.c_str(), cloud.size(),
                  SimplifyMethodName(config.simplify.method));
      std::printf("%-14s %-7s %10s %10s %10s %8s\n", "class", "role", "in", "kept", "removed", "kept%");
      for (const auto& s : result.per_class) {
        const bool known = class_map.Contains(s.label);
        const std::string name = known ? class_map.Get(s.label).name : "id " + std::to_string(s.label);
        std::printf("%-14s %-7s %10llu %10llu %10llu %7.1f%%\n", name.c_str(),
                    ClassRoleName(class_map.Role(s.label)), static_cast<unsigned long long>(s.in),
                    static_cast<unsigned long long>(s.kept), static_cast<unsigned long long>(s.removed),
                    s.in > 0 ? 100.0 * static_cast<double>(s.kept) / static_cast<double>(s.in) : 100.0);
      }
      std::printf("%-14s %-7s %10llu %10llu %10llu %7.1f%%\n", "total", "",
                  static_cast<unsigned long long>(result.in), static_cast<unsigned long long>(result.kept()),
                  static_cast<unsigned long long>(result.in - result.kept()),
                  result.in > 0 ? 100.0 * static_cast<double>(result.kept()) / static_cast<double>(result.in)
                                : 100.0);
      std::printf("time: %.3f s (%.0f points/s)\n", result.time_s,
                  result.time_s > 0.0 ? static_cast<double>(result.in) / result.time_s : 0.0);
      if (!args->out.empty()) {
        io::WriteCloudPly(args->out, ApplySimplification(cloud, result),
                          args->ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);
        spdlog::info("wrote {} points to {}", result.kept(), args->out);
      }
      return kExitOk;
    });
  });
}

}  // namespace semap::tools
