// `semap eval --json` of a written mesh, read back as a user's script would (test helper).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/tools/cli_run.h"

namespace semap::test {

// `semap eval SEQUENCE --mesh MESH --json JSON`, parsed; null (and a test failure) when the command failed.
inline nlohmann::json EvalJson(const std::filesystem::path& sequence, const std::filesystem::path& mesh,
                               const std::filesystem::path& json) {
  const CliRun r =
      RunSemap("eval " + sequence.string() + " --mesh " + mesh.string() + " --json " + json.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return {};
  return nlohmann::json::parse(std::ifstream(json));
}

}  // namespace semap::test
