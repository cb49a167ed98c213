// The semap configuration (app/: it knows every module): one options struct per stage, loaded from YAML with
// `--set key=value` overrides.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/config/pose_input.h"
#include "app/split/split_options.h"
#include "engine/depth/plane_sweep.h"
#include "engine/depth/stereo_depth.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/map/map_options.h"
#include "engine/odometry/stereo_odometry.h"
#include "engine/pipeline/pipeline.h"
#include "engine/semantics/segmenter.h"
#include "engine/sim/synth_options.h"
#include "engine/simplify/simplify.h"
#include "io/config/field_binder.h"
#include "io/frame_source.h"
#include "io/lcm/depth_frames.h"
#include "io/lcm/lcm_publisher.h"
#include "io/output/output_sinks.h"

namespace semap::app {

// A config error a user can act on: names the file and/or key.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every stage's options. Defaults are the paper's values where it gives them.
// config/default.yaml is generated from these structs (`semap config --defaults`); a test keeps it in sync.
struct Config {
  io::FrameSourceOptions input;        // where frames come from and what is loaded with them
  PoseInputOptions pose_input;         // input.poses: where the camera poses come from
  OneFrameInputOptions one_frame;      // input.one_frame_preset: a run of one frame
  sim::SynthOptions synth;             // the synthetic sequence generator (`semap synth`)
  PipelineOptions pipeline;            // stage threads, queues, modes
  io::OutputOptions output;            // files written by a run
  io::LcmOptions lcm;                  // mesh / stats publishing over LCM
  SplitOptions split;                  // depth nodes and a map node joined over LCM
  io::DepthFrameOptions depth_frames;  // how a depth node encodes its frames
  DepthAccuracyOptions eval;           // accuracy against Velodyne / exact depth
  StereoOdometryOptions odometry;      // poses from the images (input.poses)
  DepthOptions depth;                  // stereo matching and point cloud
  PlaneSweepOptions plane_sweep;       // multi-view depth where a frame has no stereo pair
  SemanticsOptions semantics;          // where per-pixel labels come from
  SimplifyOptions simplify;            // semantic point-cloud simplification (and its baselines)
  MapOptions map;                      // the Delaunay map: votes, manifold, incremental update, memory bound
};

// Lists the sections of `config` with their fields bound to its members (pointers into `config`).
std::vector<io::Section> BindSections(Config& config);

// Loads the defaults, then `preset` (YAML text, if not empty: a preset such as OneFramePresetYaml()), then
// the YAML file (if not empty), then each "section.key=value" override, then runs every section's Check().
// Unknown sections/keys, malformed values and out-of-range values throw ConfigError naming the file (or the
// preset) and the key.
Config LoadConfig(const std::filesystem::path& yaml_path, const std::vector<std::string>& overrides = {},
                  const std::string& preset = {});

// config/one_frame.yaml as it was built into the program (the file stays the one place its values are
// written): what input.one_frame_preset applies to a run of one frame.
const std::string& OneFramePresetYaml();

// The YAML text of `config` with each section and field preceded by its doc comment.
std::string DumpConfig(const Config& config);

// The "section.key" bound to the member of `config` at `member` (BindSections, each options struct's
// Describe()); asserts that one is.
std::string KeyOfMember(Config& config, const void* member);

// The "section.key" of `field` of the options struct `options` of a Config, from their declarations:
// ConfigKey(&Config::simplify, &SimplifyOptions::method) is "simplify.method". Code that names a key says
// which member it means, and the key is written once, where the member is described.
template <typename Options, typename T>
std::string ConfigKey(Options Config::*options, T Options::*field) {
  Config config;
  return KeyOfMember(config, &((config.*options).*field));
}

// A --set override of that key: "section.key=value".
template <typename Options, typename T>
std::string Override(Options Config::*options, T Options::*field, const std::string& value) {
  return ConfigKey(options, field) + "=" + value;
}

}  // namespace semap::app
