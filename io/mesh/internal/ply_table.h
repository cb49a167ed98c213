// Generic PLY parsing into columns (not API): the header's elements and properties, and every value read
// as a double (exact for every PLY scalar type except 64-bit doubles, which are kept as read).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace semap::io::mesh_internal {

enum class PlyType : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // value type (of the list items for a list)
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // list only
  // Scalar: one value per row. List: `list_counts[row]` values per row, concatenated in `values`.
  std::vector<double> values;
  std::vector<std::uint32_t> list_counts;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;

  // The property called `name`, or nullptr.
  const PlyProperty* Find(const std::string& name) const;
};

struct PlyTable {
  bool binary = true;
  std::vector<PlyElement> elements;

  // The element called `name`, or nullptr.
  const PlyElement* Find(const std::string& name) const;
};

// Reads a whole PLY file (ascii or binary_little_endian 1.0). Throws io::FileError naming `path` and the
// problem (missing file, bad header, unsupported format, truncated data, malformed value).
PlyTable ReadPlyTable(const std::filesystem::path& path);

}  // namespace semap::io::mesh_internal
