// The finalised part of a run's mesh, kept on disk while the run goes on. The map finalises what the drive
// has left behind and never changes it again (MeshDelta::finalised_triangle_ids); MeshFileSink moves those
// triangles out of its memory into a spill file, so that its memory follows the live mesh, not the whole
// drive, and reads them back once, at the end, to write mesh.ply and mesh.off.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>

#include "engine/core/mesh_delta.h"

namespace semap::io {

// An append-only file of deltas that add triangles (with the vertices they reference, as
// MeshAccumulator::TakeTriangles gives them). The format is this class's own: a magic line, then one record
// per delta (counts, then the arrays, little-endian as in memory), read back only by the same build. The file
// is created at the first Append and removed by Remove() or the destructor. Not thread-safe.
class MeshSpill {
 public:
  explicit MeshSpill(std::filesystem::path path) : path_(std::move(path)) {}
  ~MeshSpill();
  MeshSpill(const MeshSpill&) = delete;
  MeshSpill& operator=(const MeshSpill&) = delete;

  // Appends `finalised` (its added triangles and vertices; nothing else is kept), flushed to the file before
  // it returns. Throws FileError naming the file when it cannot be created or written; what was appended
  // before stays readable, and every later Append throws.
  void Append(const MeshDelta& finalised);
  // Calls `f` with each appended delta, in the order appended. Throws FileError naming the file when it
  // cannot be read back whole.
  void ForEach(const std::function<void(const MeshDelta&)>& f);
  // Deletes the file and forgets what was appended.
  void Remove();

  std::uint64_t num_triangles() const { return num_triangles_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  bool failed_ = false;
  std::uint64_t num_records_ = 0;  // complete records, on disk
  std::uint64_t num_triangles_ = 0;
};

}  // namespace semap::io
