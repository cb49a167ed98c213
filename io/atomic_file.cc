#include "io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/file_error.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// A name beside `path` that no other process writing the same file uses at the same time.
fs::path TempNameFor(const fs::path& path) {
  std::string name = ".";  // appended piecewise: GCC 12 warns (-Wrestrict, wrongly) about "." + string
  name += path.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  return path.parent_path() / name;
}

bool IsSpecialFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);
  return !ec && fs::exists(s) && !fs::is_regular_file(s) && !fs::is_directory(s);
}

}  // namespace

AtomicFile::AtomicFile(fs::path path, bool binary)
    : path_(std::move(path)), temp_(IsSpecialFile(path_) ? path_ : TempNameFor(path_)) {
  const auto mode = std::ios::out | std::ios::trunc | (binary ? std::ios::binary : std::ios::openmode{});
  out_.open(temp_, mode);
  if (!out_) {
    const std::string why = std::strerror(errno);
    throw FileError(path_, "cannot open for writing (" + why + ")");
  }
}

AtomicFile::~AtomicFile() {
  if (committed_ || temp_ == path_) return;
  out_.close();
  std::error_code ec;
  fs::remove(temp_, ec);  // best effort: the error that got us here is the one reported
}

void AtomicFile::SetBuffer(std::vector<char>* buffer) {
  out_.rdbuf()->pubsetbuf(buffer->data(), static_cast<std::streamsize>(buffer->size()));
}

void AtomicFile::Commit() {
  out_.flush();
  if (!out_) throw FileError(path_, "write failed (disk full or I/O error)");
  out_.close();
  if (!out_) throw FileError(path_, "write failed on close (disk full or I/O error)");
  if (temp_ != path_) {
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec)
      throw FileError(path_, "cannot rename " + temp_.filename().string() + " into place: " + ec.message());
  }
  committed_ = true;
}

void WriteFileAtomically(const fs::path& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.Commit();
}

void CheckWritableFolder(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) {
    throw FileError(dir, ec ? "cannot create the output folder: " + ec.message() : "is not a folder");
  }
  const fs::path probe = TempNameFor(dir / "write-probe");
  {
    std::ofstream out(probe);
    if (!out)
      throw FileError(dir, "output folder is not writable (" + std::string(std::strerror(errno)) + ")");
  }
  fs::remove(probe, ec);
}

}  // namespace semap::io
