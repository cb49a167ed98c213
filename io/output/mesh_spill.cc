#include "io/output/mesh_spill.h"

#include <string>
#include <system_error>
#include <vector>

#include "io/file_error.h"

namespace semap::io {
namespace {

constexpr char kMagic[] = "semap mesh spill 1\n";

template <typename T>
void WriteArray(std::ofstream& out, const std::vector<T>& v) {
  out.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
}

template <typename T>
void ReadArray(std::ifstream& in, std::size_t n, std::vector<T>* v) {
  v->resize(n);
  in.read(reinterpret_cast<char*>(v->data()), std::streamsize(n * sizeof(T)));
}

struct RecordHeader {
  std::uint64_t num_triangles = 0;
  std::uint64_t num_vertices = 0;
  std::uint8_t has_colors = 0;
  std::uint8_t has_labels = 0;
  std::uint8_t unused[6] = {};  // the padding, written as zeros
};
static_assert(sizeof(RecordHeader) == 24);

}  // namespace

MeshSpill::~MeshSpill() { Remove(); }

void MeshSpill::Remove() {
  num_records_ = num_triangles_ = 0;
  failed_ = false;
  if (!out_.is_open()) return;
  out_.close();
  // Only the regular file it made (never a device or anything else the path may name); nothing to report on
  // failure: a leftover file is harmless (the next run replaces it).
  std::error_code ec;
  if (std::filesystem::is_regular_file(path_, ec)) std::filesystem::remove(path_, ec);
}

void MeshSpill::Append(const MeshDelta& finalised) {
  if (finalised.added_triangle_ids.empty()) return;
  if (failed_) throw FileError(path_, "an earlier write of the spill file of the finalised mesh failed");
  if (!out_.is_open()) {
    out_.open(path_, std::ios::binary | std::ios::trunc);
    if (!out_) {
      failed_ = true;
      throw FileError(path_, "cannot create the spill file of the finalised mesh");
    }
    out_.write(kMagic, sizeof(kMagic) - 1);
  }
  RecordHeader h;
  h.num_triangles = finalised.added_triangle_ids.size();
  h.num_vertices = finalised.vertex_ids.size();
  h.has_colors = !finalised.vertex_colors_rgb.empty();
  h.has_labels = !finalised.vertex_labels.empty();
  out_.write(reinterpret_cast<const char*>(&h), sizeof(h));
  WriteArray(out_, finalised.added_triangle_ids);
  WriteArray(out_, finalised.added_triangles);
  WriteArray(out_, finalised.vertex_ids);
  WriteArray(out_, finalised.vertex_positions);
  if (h.has_colors) WriteArray(out_, finalised.vertex_colors_rgb);
  if (h.has_labels) WriteArray(out_, finalised.vertex_labels);
  out_.flush();
  if (!out_) {
    failed_ = true;
    throw FileError(path_, "cannot write the spill file of the finalised mesh (disk full?)");
  }
  ++num_records_;
  num_triangles_ += h.num_triangles;
}

void MeshSpill::ForEach(const std::function<void(const MeshDelta&)>& f) {
  if (num_records_ == 0) return;
  std::ifstream in(path_, std::ios::binary);
  std::string magic(sizeof(kMagic) - 1, '\0');
  in.read(magic.data(), std::streamsize(magic.size()));
  if (!in || magic != kMagic)
    throw FileError(path_, "the spill file of the finalised mesh is not this run's");
  MeshDelta d;
  for (std::uint64_t r = 0; r < num_records_; ++r) {
    RecordHeader h;
    in.read(reinterpret_cast<char*>(&h), sizeof(h));
    if (!in) throw FileError(path_, "the spill file of the finalised mesh is truncated");
    ReadArray(in, h.num_triangles, &d.added_triangle_ids);
    ReadArray(in, h.num_triangles, &d.added_triangles);
    ReadArray(in, h.num_vertices, &d.vertex_ids);
    ReadArray(in, h.num_vertices, &d.vertex_positions);
    ReadArray(in, h.has_colors ? h.num_vertices : 0, &d.vertex_colors_rgb);
    ReadArray(in, h.has_labels ? h.num_vertices : 0, &d.vertex_labels);
    if (!in) throw FileError(path_, "the spill file of the finalised mesh is truncated");
    f(d);
  }
}

}  // namespace semap::io
