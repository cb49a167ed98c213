// What the writers of generated data sets share: text files and folders (images: io/image/image_files.h).
#pragma once

#include <filesystem>
#include <string>

#include "io/file_error.h"

namespace semap::io::synth_internal {

// Writes `text` to `path` as it is. Throws FileError naming the path when it cannot be written.
void WriteText(const std::filesystem::path& path, const std::string& text);

// Creates `folder` and its parents. Throws FileError naming it when that fails.
void CreateFolders(const std::filesystem::path& folder);

}  // namespace semap::io::synth_internal
