// The error thrown for a file or folder that cannot be read or written: the message names the path.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace semap::io {

// A file or folder that cannot be read or written (missing, unreadable, truncated, malformed). what() is
// "<path>: <problem>".
class FileError : public std::runtime_error {
 public:
  FileError(const std::filesystem::path& path, const std::string& problem)
      : std::runtime_error(path.string() + ": " + problem), path_(path) {}
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace semap::io
