// `semap map-sfm INPUT --format colmap|openmvg|slam-json [--incremental] --out DIR`: the Delaunay map of an
// existing structure-from-motion / SLAM reconstruction (cameras and points), batch or view by view
// (app/sfm/map_sfm_run.h does the run).
#include <memory>

#include "app/sfm/map_sfm_run.h"
#include "io/sfm/sfm_reconstruction.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct MapSfmArgs {
  CommonArgs common;
  std::string input;
  std::string format;
  bool incremental = false;
  std::string out;
  std::string method;
  std::string lcm_url;
  double progress_s = 1.0;
};

std::vector<std::string> Overrides(const MapSfmArgs& a) {
  using app::Config;
  using app::Override;
  std::vector<std::string> o = a.common.overrides;
  if (!a.out.empty()) o.push_back(Override(&Config::output, &io::OutputOptions::dir, a.out));
  if (!a.method.empty()) o.push_back(Override(&Config::simplify, &SimplifyOptions::method, a.method));
  if (!a.lcm_url.empty()) {
    o.push_back(Override(&Config::lcm, &io::LcmOptions::enabled, "true"));
    o.push_back(Override(&Config::lcm, &io::LcmOptions::url, a.lcm_url));
  }
  return o;
}

int Run(const MapSfmArgs& args) {
  const app::Config config = app::LoadConfig(args.common.config_path, Overrides(args));
  app::MapSfm(config, {args.input, io::SfmFormatFromName(args.format), args.incremental, args.progress_s});
  return kExitOk;
}

}  // namespace

void RegisterMapSfmCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<MapSfmArgs>();
  auto* cmd =
      app.add_subcommand("map-sfm",
                         "Delaunay map of an existing SfM/SLAM reconstruction (COLMAP, OpenMVG, or the 2018 "
                         "manifold mapper's SLAM JSON): batch, or view by view with --incremental");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option(
         "INPUT", args->input,
         "COLMAP model folder (cameras/images/points3D .txt or .bin), OpenMVG sfm_data.json, or SLAM JSON")
      ->required();
  cmd->add_option("--format", args->format, "input format")
      ->required()
      ->check(CLI::IsMember({"colmap", "openmvg", "slam-json"}));
  cmd->add_flag("--incremental", args->incremental,
                "add the views in their order as keyframes to the incremental map (default: one batch map)");
  cmd->add_option("--out", args->out, "output folder (output.dir)");
  cmd->add_option(
      "--method", args->method,
      "simplification of labelled points, e.g. PS or O (simplify.method; needs per-point labels)");
  cmd->add_option("--lcm-url", args->lcm_url,
                  "publish over LCM at this URL, e.g. udpm://239.255.76.67:7667?ttl=0 (lcm.url)");
  cmd->add_option("--progress-interval", args->progress_s, "seconds between progress lines")
      ->capture_default_str();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Run(*args); }); });
}

}  // namespace semap::tools
