// `semap synth`: generate a synthetic KITTI-raw street sequence, or a multi-view set in the Strecha layout,
// with exact ground truth (the options from the config and the command line here, the generation in
// app/synth/generate.h).
#include <spdlog/spdlog.h>

#include <map>

#include "app/synth/generate.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct SynthArgs {
  CommonArgs common;
  std::string layout = "kitti-raw";
  std::string preset;
  int frames = -1;
  std::int64_t seed = -1;
  double speed_mps = -1.0;
  int turns = -1;
  std::string out;
};

// The multi-view set: --frames is its number of views, --seed its seed; the street's options do not apply.
int RunMultiViewSynth(const SynthArgs& a, sim::SynthOptions synth) {
  if (!a.preset.empty() || a.speed_mps >= 0.0 || a.turns >= 0) {
    spdlog::error("--preset, --speed-mps and --turns are options of the street (--layout kitti-raw)");
    return kExitUsage;
  }
  sim::MultiViewSetOptions set;
  if (a.frames >= 0) set.num_views = a.frames;
  if (a.seed >= 0) synth.seed = static_cast<std::uint64_t>(a.seed);
  synth.Check();
  set.Check();
  app::GenerateMultiViewSet(synth, set, a.out);
  return kExitOk;
}

int RunSynth(const SynthArgs& a) {
  app::Config config = LoadConfigFrom(a.common);
  if (a.layout == "strecha") return RunMultiViewSynth(a, config.synth);
  sim::SynthOptions o = config.synth;
  if (!a.preset.empty()) {
    const std::map<std::string, sim::ScenePreset> presets = {{"urban", sim::ScenePreset::kUrban},
                                                             {"vegetated", sim::ScenePreset::kVegetated},
                                                             {"mixed", sim::ScenePreset::kMixed}};
    o.preset = presets.at(a.preset);  // CLI11 already restricted the value
  }
  if (a.frames >= 0) o.num_frames = a.frames;
  if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
  if (a.speed_mps >= 0.0) o.speed_mps = a.speed_mps;
  if (a.turns >= 0) o.num_turns = a.turns;
  o.Check();

  app::GenerateSequence(o, a.out);
  return kExitOk;
}

}  // namespace

void RegisterSynthCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "synth",
      "Generate a synthetic street sequence in the KITTI raw layout with exact depth, labels, poses, "
      "Velodyne scans and the scene mesh, or (--layout strecha) a calibrated multi-view set like "
      "fountain-P11: "
      "an ornate textured object before a wall on the ground, seen by views on an arc at 4-10 m, 768x512 px, "
      "written as images/NNNN.png, images/K.txt, gt_dense_cameras/NNNN.png.camera, labels/NNNN.png "
      "(Cityscapes "
      "ids: ground sidewalk, wall building, object pole), depth/NNNN.png (exact depth, uint16 mm, camera z) "
      "and scene_mesh.ply");
  auto args = std::make_shared<SynthArgs>();
  AddCommonOptions(cmd, &args->common);
  cmd->add_option(
         "--layout", args->layout,
         "kitti-raw: a street sequence (default); strecha: a multi-view set of 11 views (--frames sets "
         "the number of views, --seed the seed; synth.image_noise_sigma, blur_sigma_px, vignetting, "
         "exposure_variation and near_m apply)")
      ->check(CLI::IsMember({"kitti-raw", "strecha"}));
  cmd->add_option("--preset", args->preset, "scene composition (default: synth.preset)")
      ->check(CLI::IsMember({"urban", "vegetated", "mixed"}));
  cmd->add_option(
         "--frames", args->frames,
         "number of frames (default: synth.num_frames); with --layout strecha, of views (default 11)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--seed", args->seed, "random seed (default: synth.seed)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--speed-mps", args->speed_mps, "vehicle speed in m/s (default: synth.speed_mps)")
      ->check(CLI::Range(0.0, 40.0));
  cmd->add_option("--turns", args->turns, "turns at intersections (default: synth.num_turns)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", args->out,
                  "output root folder (the KITTI DATE folder is created in it; a Strecha set's folders are)")
      ->required();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return RunSynth(*args); }); });
}

}  // namespace semap::tools
