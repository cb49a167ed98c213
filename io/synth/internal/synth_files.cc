#include "io/synth/internal/synth_files.h"

#include <fstream>

namespace semap::io::synth_internal {

namespace fs = std::filesystem;

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw FileError(path, "cannot open for writing");
  os << text;
  if (!os) throw FileError(path, "write failed");
}

void CreateFolders(const fs::path& folder) {
  try {
    fs::create_directories(folder);
  } catch (const fs::filesystem_error& e) {
    throw FileError(folder, std::string("cannot create folders: ") + e.what());
  }
}

}  // namespace semap::io::synth_internal
