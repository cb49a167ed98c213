// The options every sequence bench program shares (the sequence, --frames, --config, --set) and the frame
// source they open, so that each program declares only its own.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "io/frame_source.h"

namespace semap::bench {

struct SequenceArgs {
  std::string sequence;
  std::string config_path;
  std::vector<std::string> overrides;
  int frames = 0;  // 0 = all

  // Adds the shared options to `app`; `what` describes the sequence the program needs.
  void AddTo(CLI::App& app, const std::string& what) {
    app.add_option("sequence", sequence, what)->required();
    app.add_option("--frames", frames, "frames to use, 0 = all")->check(CLI::NonNegativeNumber);
    app.add_option("--config", config_path, "YAML config (the run's)");
    app.add_option("--set", overrides, "section.key=value overrides (the run's)");
  }

  app::Config LoadConfig() const { return app::LoadConfig(config_path, overrides); }

  // The frame source's options from `config`, with --frames and the Velodyne as asked.
  io::FrameSourceOptions Input(const app::Config& config, bool load_velodyne) const {
    io::FrameSourceOptions input = config.input;
    input.load_velodyne = load_velodyne;
    if (frames > 0) input.max_frames = frames;
    return input;
  }
};

}  // namespace semap::bench
