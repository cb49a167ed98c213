// Files written whole or not at all: the content goes to a temporary name in the same folder and is renamed
// over the target once complete, so that a process killed mid-write, a full disk or a failed write never
// leaves a truncated file under the final name (the target keeps its old content, or does not appear).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace semap::io {

// One file being written. Throws FileError naming the final path when the temporary file cannot be
// created, and from Commit() when a write failed (disk full, I/O error) or the rename fails.
// A target that exists and is not a regular file (a device such as /dev/stdout or /dev/full, a FIFO) is
// written in place: there is nothing to rename, and write errors are still reported by Commit().
// Not a durability guarantee against power loss (no fsync): it guards against partial files.
class AtomicFile {
 public:
  // `binary`: no newline translation (the same on Linux; stated for the reader).
  explicit AtomicFile(std::filesystem::path path, bool binary = false);
  // Removes the temporary file when Commit() was not reached (an exception while writing).
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // A larger stream buffer (call before writing); the buffer must outlive the file.
  void SetBuffer(std::vector<char>* buffer);
  // Flushes, closes, checks and renames the file into place.
  void Commit();

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_;  // == path_ when written in place
  std::ofstream out_;
  bool committed_ = false;
};

// Writes `text` to `path` atomically (see AtomicFile).
void WriteFileAtomically(const std::filesystem::path& path, const std::string& text);

// Throws FileError naming `dir` unless files can be created in it (creating it when missing): what a run
// checks before its first frame so that an unusable output folder costs no work.
void CheckWritableFolder(const std::filesystem::path& dir);

}  // namespace semap::io
