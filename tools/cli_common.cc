#include "tools/cli_common.h"

#include <spdlog/spdlog.h>

#include <limits>
#include <stdexcept>

#include "engine/core/check.h"

namespace semap::tools {

void AddCommonOptions(CLI::App* cmd, CommonArgs* args) {
  cmd->add_option("--config", args->config_path, "YAML config file (see config/default.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", args->overrides, "override a config value: section.key=value (repeatable)");
  cmd->add_option("--log-level", args->log_level, "trace|debug|info|warn|error|off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
}

CLI::Validator FrameCountCheck() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        long long n = -1;
        std::size_t used = 0;
        try {
          n = std::stoll(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || n < 0 || n > std::numeric_limits<int>::max()) {
          return "'" + text + "' is not a number of frames (a whole number >= 0; 0 = all)";
        }
        return {};
      },
      "FRAMES>=0");
}

app::Config LoadConfigFrom(const CommonArgs& args) {
  return app::LoadConfig(args.config_path, args.overrides);
}

int RunGuarded(const CommonArgs& args, const std::function<int()>& body) {
  spdlog::set_level(spdlog::level::from_str(args.log_level));
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  try {
    return body();
  } catch (const app::ConfigError& e) {
    spdlog::error("{}", e.what());
    return kExitUsage;
  } catch (const InvalidOption& e) {
    spdlog::error("invalid option {}", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
}

}  // namespace semap::tools
