// A small generated sequence for the CLI tests that stream (table, compare): made once per test binary with
// `semap synth` at a reduced image size.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::test {

// The sequence folder with `frames` urban frames (seed 1), generated on first use.
// (TempDir() is per test and emptied on each call, so the sequence lives in the process's folder.)
inline std::filesystem::path SmallGeneratedSequence(int frames) {
  const std::filesystem::path dir = ProcessTempRoot() / ("small_urban_" + std::to_string(frames));
  if (!std::filesystem::exists(dir / "done")) {
    const CliRun r =
        RunSemap("synth --preset urban --seed 1 --frames " + std::to_string(frames) +
                 " --set synth.image_width_px=480 --set synth.image_height_px=144"
                 " --set synth.cx_px=240 --set synth.cy_px=72 --set synth.lidar_azimuth_steps=512"
                 " --out " +
                 dir.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::filesystem::create_directories(dir / "done");
  }
  return dir;
}

}  // namespace semap::test
