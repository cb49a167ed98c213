// Class maps as YAML files:
//
//   scheme: cityscapes          # name of the id scheme
//   unlabelled_id: 0            # id of pixels/points with no semantic information (must be a class)
//   classes:
//     - {id: 1, name: Road, color: [81, 0, 81], role: ground}    # role: ground | wall | keep
//
// Ids are 0..255 and unique; names are unique (case-insensitive); colours are RGB 0..255.
#pragma once

#include <filesystem>

#include "engine/core/class_map.h"
#include "io/file_error.h"

namespace semap::io {

// Reads a class map; an empty path gives ClassMap::Cityscapes(). Throws FileError naming the file and the
// offending entry (e.g. "classes[3].role: 'floor' is not one of ground|wall|keep").
ClassMap LoadClassMap(const std::filesystem::path& path);

// Writes `map` in the format above (readable back by LoadClassMap).
void SaveClassMap(const std::filesystem::path& path, const ClassMap& map);

}  // namespace semap::io
