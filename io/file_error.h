// The errors thrown for a file or folder that cannot be read or written: the message names the path (and,
// for a malformed entry of a structured file, the entry and the field).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

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

// A malformed entry of a structured file (a line, a JSON object, a binary record). what() is
// "<path>: <entry>: <field>: <problem>", e.g. "sfm_data.json: structure[3] (key 17): observations[0].key:
// view 9 does not exist"; an empty entry or field is left out.
class ParseError : public FileError {
 public:
  ParseError(const std::filesystem::path& path, std::string entry, std::string field,
             const std::string& problem)
      : FileError(path, Join(entry, field, problem)), entry_(std::move(entry)), field_(std::move(field)) {}
  const std::string& entry() const { return entry_; }
  const std::string& field() const { return field_; }

 private:
  static std::string Join(const std::string& entry, const std::string& field, const std::string& problem) {
    std::string s;
    for (const std::string* part : {&entry, &field}) {
      if (!part->empty()) s += *part + ": ";
    }
    return s + problem;
  }
  std::string entry_;
  std::string field_;
};

}  // namespace semap::io
