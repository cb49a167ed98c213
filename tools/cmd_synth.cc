// `semap synth`: generate a synthetic KITTI-raw street sequence with exact ground truth.
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <map>

#include "engine/core/class_map.h"
#include "io/synth/kitti_raw_writer.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct SynthArgs {
  CommonArgs common;
  std::string preset;
  int frames = -1;
  std::int64_t seed = -1;
  double speed_mps = -1.0;
  int turns = -1;
  std::string out;
};

int RunSynth(const SynthArgs& a) {
  app::Config config = LoadConfigFrom(a.common);
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

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  spdlog::info("synth: preset {}, {} frames, seed {}, {:.1f} m/s, {} turns -> {}",
               sim::ScenePresetName(o.preset), o.num_frames, o.seed, o.speed_mps, o.num_turns, a.out);
  const sim::SyntheticSequence sequence(o);
  const double build_s = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("scene: {} triangles, {} chunks, BVH {} nodes; drive {:.0f} m with {} turns ({:.2f} s)",
               sequence.scene().num_triangles(), sequence.scene().chunks.size(), sequence.bvh().num_nodes(),
               sequence.trajectory().length_m(), sequence.trajectory().num_turns(), build_s);

  auto last_report = Clock::now();
  const auto t1 = Clock::now();
  const io::SynthWriteSummary summary = io::WriteSyntheticKittiRaw(sequence, a.out, [&](int done, int total) {
    const auto now = Clock::now();
    if (done == total || now - last_report > std::chrono::seconds(2)) {
      last_report = now;
      const double s = std::chrono::duration<double>(now - t1).count();
      spdlog::info("frame {}/{} ({:.1f} frames/s)", done, total, done / std::max(s, 1e-9));
    }
  });
  const double write_s = std::chrono::duration<double>(Clock::now() - t1).count();
  const double total_s = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("wrote {} frames to {} in {:.2f} s ({:.2f} frames/s rendering+writing, {:.2f} s total)",
               summary.num_frames, summary.layout.drive_dir.string(), write_s, summary.num_frames / write_s,
               total_s);
  spdlog::info("velodyne: {:.0f} points per scan on average",
               static_cast<double>(summary.lidar_points) / std::max(1, summary.num_frames));
  const ClassMap classes = ClassMap::Cityscapes();
  const auto& h = summary.label_pixels;
  spdlog::info(
      "class composition (pixels of image_02): ground {:.1f}%, wall {:.1f}%, vegetation {:.1f}%, "
      "car {:.1f}%, sky {:.1f}%",
      100.0 * h.RoleShare(classes, ClassRole::kGround), 100.0 * h.RoleShare(classes, ClassRole::kWall),
      100.0 * h.Share(sim::label::kVegetation), 100.0 * h.Share(sim::label::kCar),
      100.0 * h.Share(sim::label::kSky));
  return kExitOk;
}

}  // namespace

void RegisterSynthCommand(CLI::App& app, int* exit_code) {
  auto* cmd = app.add_subcommand(
      "synth",
      "Generate a synthetic street sequence in the KITTI raw layout with exact depth, labels, poses, "
      "Velodyne scans and the scene mesh");
  auto args = std::make_shared<SynthArgs>();
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("--preset", args->preset, "scene composition (default: synth.preset)")
      ->check(CLI::IsMember({"urban", "vegetated", "mixed"}));
  cmd->add_option("--frames", args->frames, "number of frames (default: synth.num_frames)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--seed", args->seed, "random seed (default: synth.seed)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--speed-mps", args->speed_mps, "vehicle speed in m/s (default: synth.speed_mps)")
      ->check(CLI::Range(0.0, 40.0));
  cmd->add_option("--turns", args->turns, "turns at intersections (default: synth.num_turns)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", args->out, "output root folder (the KITTI DATE folder is created in it)")
      ->required();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return RunSynth(*args); }); });
}

}  // namespace semap::tools
