// Shared helper of the libFuzzer targets: the parsers under test read files, so each input is written to a
// per-process temporary file first. A parser may reject any input with an exception (a user error); a crash,
// an assertion or a sanitizer report is a bug.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace semap::fuzz {

inline std::filesystem::path ScratchDir() {
  const auto dir = std::filesystem::temp_directory_path() / ("semap_fuzz_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path WriteInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const auto path = ScratchDir() / name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace semap::fuzz
