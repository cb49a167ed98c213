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

inline CliRun RunSemap(const std::string& args) {
  CliRun r;
  const std::string cmd = std::string(SEMAP_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1000 - WTERMSIG(status);
  return r;
}

}  // namespace semap::test
