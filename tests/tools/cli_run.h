// Runs the built `semap` executable as a user would and captures its output (test helper).
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace semap::test {

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
  bool Has(const std::string& text) const { return output.find(text) != std::string::npos; }
};

// `semap synth` settings for a small generated sequence that a run streams in seconds: small images, a
// sparse scanner.
inline const std::string kSmallSynth =
    " --set synth.image_width_px=320 --set synth.image_height_px=96 --set synth.cx_px=160"
    " --set synth.cy_px=48 --set synth.lidar_azimuth_steps=256";

// Runs `command` through the shell, stderr merged into the output.
inline CliRun RunShell(const std::string& command) {
  CliRun r;
  const std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1000 - WTERMSIG(status);
  return r;
}

// Runs the semap executable under test (SEMAP_EXE) with `args`.
inline CliRun RunSemap(const std::string& args) { return RunShell(std::string(SEMAP_EXE) + " " + args); }

}  // namespace semap::test
