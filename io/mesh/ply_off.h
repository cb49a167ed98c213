// Mesh and point-cloud files: PLY (binary little-endian or ASCII; MeshLab/Open3D property names) and
// OFF (ASCII, the format whose size the paper reports). Every function throws io::FileError naming the
// path and the problem on a missing, unwritable, truncated or malformed file.
#pragma once

#include <cstdint>
#include <filesystem>

#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh.h"
#include "io/file_error.h"

namespace semap::io {

enum class PlyEncoding { kBinaryLittleEndian, kAscii };

// Vertex properties: x y z (float, or double when `double_precision`), red green blue (uchar) when the
// mesh has colours, label (uchar) when it has labels; faces: vertex_indices (uchar count, int indices).
void WriteMeshPly(const std::filesystem::path& path, const Mesh& mesh,
                  PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian, bool double_precision = false);
Mesh ReadMeshPly(const std::filesystem::path& path);
// `mesh` with its coordinates rounded to float32, as WriteMeshPly stores them (not double_precision): what
// ReadMeshPly of the written file returns, without the file.
Mesh AsStoredInPly(Mesh mesh);

// Polygons with more than 3 vertices are read as triangle fans; float colours are taken in [0, 1].
// OFF: "OFF", counts, vertices, "3 i j k" faces; colours and labels are not stored. Coordinates are written
// at float precision (the shortest text that reads back to the same float).
void WriteMeshOff(const std::filesystem::path& path, const Mesh& mesh);
Mesh ReadMeshOff(const std::filesystem::path& path);
// ReadMeshOff for a path ending in .off, ReadMeshPly otherwise.
Mesh ReadMesh(const std::filesystem::path& path);
// Bytes of the mesh written as ASCII OFF (the paper's mesh-size measure), without writing a file.
std::uint64_t OffSizeBytes(const Mesh& mesh);

// Point clouds: element vertex with x y z, red green blue, label, and (when present) camera_index (uint),
// confidence (float), pixel_u pixel_v (float); the observing cameras as an extra element `camera` (double x
// y z, int frame_id) that MeshLab/Open3D skip. Absent attributes are not written and read back empty.
void WriteCloudPly(const std::filesystem::path& path, const LabelledCloud& cloud,
                   PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian, bool double_precision = false);
LabelledCloud ReadCloudPly(const std::filesystem::path& path);

}  // namespace semap::io
