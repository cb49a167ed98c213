#include "io/mesh/ply_off.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <vector>

#include "engine/core/check.h"
#include "io/atomic_file.h"
#include "io/mesh/internal/ply_table.h"

namespace semap::io {
namespace {

using mesh_internal::PlyElement;
using mesh_internal::PlyProperty;
using mesh_internal::PlyTable;

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");

// Size of the write buffer of the file streams.
constexpr size_t kWriteBufferBytes = 1 << 20;

// A value formatted for ASCII files: integers as is; floating-point values as the shortest text that reads
// back to the same value of their type (float or double).
template <typename T>
std::string_view FormatNumber(T value, char (&buf)[64]) {
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  SEMAP_ASSERT(ec == std::errc(), "to_chars failed");
  return {buf, static_cast<size_t>(ptr - buf)};
}

// Buffered output file that writes PLY values in either encoding. Errors throw FileError(path).
class PlyOut {
 public:
  // Written under a temporary name and renamed into place by Close() (see AtomicFile).
  PlyOut(const std::filesystem::path& path, PlyEncoding encoding)
      : ascii_(encoding == PlyEncoding::kAscii),
        buffer_(kWriteBufferBytes),
        file_(path, /*binary=*/true),
        out_(file_.stream()) {
    file_.SetBuffer(&buffer_);
  }

  bool ascii() const { return ascii_; }
  void Text(std::string_view s) { out_.write(s.data(), static_cast<std::streamsize>(s.size())); }

  // One value of a row; `first` = no separator before it (ASCII).
  template <typename T>
  void Value(T v, bool first = false) {
    if (ascii_) {
      if (!first) out_.put(' ');
      char buf[64];
      if constexpr (sizeof(T) == 1) {
        Text(FormatNumber(static_cast<int>(v), buf));
      } else {
        Text(FormatNumber(v, buf));
      }
    } else {
      out_.write(reinterpret_cast<const char*>(&v), sizeof(T));
    }
  }
  void EndRow() {
    if (ascii_) out_.put('\n');
  }

  void Close() { file_.Commit(); }

 private:
  bool ascii_;
  std::vector<char> buffer_;  // declared before file_: it outlives the stream using it
  AtomicFile file_;
  std::ostream& out_;
};

std::string HeaderStart(PlyEncoding encoding) {
  return std::string("ply\nformat ") + (encoding == PlyEncoding::kAscii ? "ascii" : "binary_little_endian") +
         " 1.0\ncomment written by semap\n";
}

template <typename T>
void PutXyz(PlyOut& out, const Eigen::Vector3d& p) {
  out.Value(static_cast<T>(p.x()), true);
  out.Value(static_cast<T>(p.y()));
  out.Value(static_cast<T>(p.z()));
}

void PutRgb(PlyOut& out, const std::array<std::uint8_t, 3>& c) {
  out.Value(c[0]);
  out.Value(c[1]);
  out.Value(c[2]);
}

// --- reading helpers ---------------------------------------------------------------------------------------

const PlyProperty& Require(const std::filesystem::path& path, const PlyElement& e, const std::string& name) {
  const PlyProperty* p = e.Find(name);
  if (p == nullptr || p->is_list) {
    throw FileError(path, "element '" + e.name + "' has no scalar property '" + name + "'");
  }
  return *p;
}

const PlyProperty* Optional(const PlyElement& e, const std::string& name) {
  const PlyProperty* p = e.Find(name);
  return (p != nullptr && !p->is_list) ? p : nullptr;
}

const PlyElement& RequireElement(const std::filesystem::path& path, const PlyTable& t,
                                 const std::string& name) {
  const PlyElement* e = t.Find(name);
  if (e == nullptr) throw FileError(path, "no '" + name + "' element");
  return *e;
}

std::vector<Eigen::Vector3d> ReadXyz(const std::filesystem::path& path, const PlyElement& e) {
  const auto& x = Require(path, e, "x").values;
  const auto& y = Require(path, e, "y").values;
  const auto& z = Require(path, e, "z").values;
  std::vector<Eigen::Vector3d> out(e.count);
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = {x[i], y[i], z[i]};
    if (!out[i].allFinite()) {
      throw FileError(path,
                      "element '" + e.name + "' row " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  return out;
}

std::uint8_t ToByte(double v, bool unit_range) {
  if (unit_range) v *= 255.0;
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// red green blue when all three are present; float colours are taken in [0, 1] (PLY convention).
std::vector<std::array<std::uint8_t, 3>> ReadRgb(const PlyElement& e) {
  const PlyProperty* r = Optional(e, "red");
  const PlyProperty* g = Optional(e, "green");
  const PlyProperty* b = Optional(e, "blue");
  if (r == nullptr || g == nullptr || b == nullptr) return {};
  const bool unit =
      r->type == mesh_internal::PlyType::kFloat32 || r->type == mesh_internal::PlyType::kFloat64;
  std::vector<std::array<std::uint8_t, 3>> out(e.count);
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = {ToByte(r->values[i], unit), ToByte(g->values[i], unit), ToByte(b->values[i], unit)};
  }
  return out;
}

std::vector<Label> ReadLabels(const std::filesystem::path& path, const PlyElement& e) {
  const PlyProperty* l = Optional(e, "label");
  if (l == nullptr) return {};
  std::vector<Label> out(e.count);
  for (size_t i = 0; i < out.size(); ++i) {
    const double v = l->values[i];
    if (v < 0 || v > std::numeric_limits<Label>::max() || v != std::floor(v)) {
      throw FileError(path, "vertex " + std::to_string(i) + " has an invalid label " + std::to_string(v));
    }
    out[i] = static_cast<Label>(v);
  }
  return out;
}

[[noreturn]] void BadIndex(const std::filesystem::path& path, const char* what, size_t face, double index,
                           size_t num_vertices) {
  std::ostringstream os;
  os << what << " " << face << " refers to vertex " << index << " but the file has " << num_vertices
     << " vertices";
  throw FileError(path, os.str());
}

// Appends the polygon `idx` as a triangle fan (a triangle stays as is).
void AddPolygon(const std::filesystem::path& path, const char* what, size_t face,
                const std::vector<double>& idx, size_t num_vertices,
                std::vector<std::array<std::uint32_t, 3>>* triangles) {
  if (idx.size() < 3) {
    throw FileError(path, std::string(what) + " " + std::to_string(face) + " has " +
                              std::to_string(idx.size()) + " vertices (at least 3 needed)");
  }
  for (double i : idx) {
    if (i < 0 || i >= static_cast<double>(num_vertices)) BadIndex(path, what, face, i, num_vertices);
  }
  for (size_t k = 1; k + 1 < idx.size(); ++k) {
    triangles->push_back({static_cast<std::uint32_t>(idx[0]), static_cast<std::uint32_t>(idx[k]),
                          static_cast<std::uint32_t>(idx[k + 1])});
  }
}

// --- OFF
// -----------------------------------------------------------------------------------------------------

// Emits the ASCII OFF text of `mesh` to `sink(std::string_view)`: shared by the writer and OffSizeBytes so
// the two agree byte for byte. Coordinates are written at float precision (shortest round-trip text).
template <typename Sink>
void EmitOff(const Mesh& mesh, Sink&& sink) {
  char buf[64];
  sink("OFF\n");
  sink(FormatNumber(mesh.num_vertices(), buf));
  sink(" ");
  sink(FormatNumber(mesh.num_triangles(), buf));
  sink(" 0\n");
  for (const auto& v : mesh.vertices) {
    sink(FormatNumber(static_cast<float>(v.x()), buf));
    sink(" ");
    sink(FormatNumber(static_cast<float>(v.y()), buf));
    sink(" ");
    sink(FormatNumber(static_cast<float>(v.z()), buf));
    sink("\n");
  }
  for (const auto& t : mesh.triangles) {
    sink("3 ");
    sink(FormatNumber(t[0], buf));
    sink(" ");
    sink(FormatNumber(t[1], buf));
    sink(" ");
    sink(FormatNumber(t[2], buf));
    sink("\n");
  }
}

// Numbers of one OFF line (comments after '#' removed). Throws on a token that is not a number.
std::vector<double> OffNumbers(const std::filesystem::path& path, const std::string& line, int line_no) {
  std::vector<double> out;
  const std::string_view text(line.data(), std::min(line.find('#'), line.size()));
  size_t pos = 0;
  while (pos < text.size()) {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    if (pos >= text.size()) break;
    size_t end = pos;
    while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end]))) ++end;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(text.data() + pos, text.data() + end, v);
    if (ec != std::errc() || ptr != text.data() + end || !std::isfinite(v)) {
      throw FileError(path, "line " + std::to_string(line_no) + ": malformed number '" +
                                std::string(text.substr(pos, end - pos)) + "'");
    }
    out.push_back(v);
    pos = end;
  }
  return out;
}

}  // namespace

// --- PLY mesh
// ------------------------------------------------------------------------------------------------

void WriteMeshPly(const std::filesystem::path& path, const Mesh& mesh, PlyEncoding encoding,
                  bool double_precision) {
  SEMAP_ASSERT(mesh.IsConsistent(), "inconsistent mesh written to " << path);
  const bool colors = !mesh.colors_rgb.empty();
  const bool labels = !mesh.labels.empty();
  std::ostringstream h;
  h << HeaderStart(encoding) << "element vertex " << mesh.num_vertices() << "\n";
  const char* coord = double_precision ? "double" : "float";
  h << "property " << coord << " x\nproperty " << coord << " y\nproperty " << coord << " z\n";
  if (colors) h << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (labels) h << "property uchar label\n";
  h << "element face " << mesh.num_triangles() << "\nproperty list uchar int vertex_indices\nend_header\n";

  PlyOut out(path, encoding);
  out.Text(h.str());
  for (size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (double_precision) {
      PutXyz<double>(out, mesh.vertices[i]);
    } else {
      PutXyz<float>(out, mesh.vertices[i]);
    }
    if (colors) PutRgb(out, mesh.colors_rgb[i]);
    if (labels) out.Value(mesh.labels[i]);
    out.EndRow();
  }
  for (const auto& t : mesh.triangles) {
    out.Value(std::uint8_t{3}, true);
    for (auto i : t) out.Value(static_cast<std::int32_t>(i));
    out.EndRow();
  }
  out.Close();
}

Mesh AsStoredInPly(Mesh mesh) {
  for (Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      // Through a volatile: GCC 12 at -O3 dropped the plain `v.cast<float>().cast<double>()` round trip for
      // some vertices of such a loop (2 of 1,051 kept their double value; `semap run --eval` then differed
      // from `semap eval` of mesh.ply by one pixel).
      volatile float stored = static_cast<float>(v[k]);
      v[k] = stored;
    }
  }
  return mesh;
}

Mesh ReadMeshPly(const std::filesystem::path& path) {
  const PlyTable table = mesh_internal::ReadPlyTable(path);
  const PlyElement& v = RequireElement(path, table, "vertex");
  Mesh mesh;
  mesh.vertices = ReadXyz(path, v);
  mesh.colors_rgb = ReadRgb(v);
  mesh.labels = ReadLabels(path, v);
  if (const PlyElement* f = table.Find("face")) {
    const PlyProperty* idx = f->Find("vertex_indices");
    if (idx == nullptr) idx = f->Find("vertex_index");
    if (idx == nullptr || !idx->is_list) {
      throw FileError(path, "element 'face' has no list property 'vertex_indices'");
    }
    mesh.triangles.reserve(f->count);
    std::vector<double> poly;
    size_t offset = 0;
    for (size_t i = 0; i < f->count; ++i) {
      poly.assign(idx->values.begin() + offset, idx->values.begin() + offset + idx->list_counts[i]);
      offset += idx->list_counts[i];
      AddPolygon(path, "face", i, poly, mesh.num_vertices(), &mesh.triangles);
    }
  }
  return mesh;
}

// --- OFF
// -----------------------------------------------------------------------------------------------------

void WriteMeshOff(const std::filesystem::path& path, const Mesh& mesh) {
  SEMAP_ASSERT(mesh.IsConsistent(), "inconsistent mesh written to " << path);
  PlyOut out(path, PlyEncoding::kAscii);
  EmitOff(mesh, [&out](std::string_view s) { out.Text(s); });
  out.Close();
}

std::uint64_t OffSizeBytes(const Mesh& mesh) {
  std::uint64_t bytes = 0;
  EmitOff(mesh, [&bytes](std::string_view s) { bytes += s.size(); });
  return bytes;
}

Mesh ReadMeshOff(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "file not found");
  std::string line;
  int line_no = 0;
  // The next line holding numbers (blank and comment-only lines skipped), or false at the end of the file.
  auto next = [&](std::vector<double>* numbers) {
    while (std::getline(in, line)) {
      ++line_no;
      *numbers = OffNumbers(path, line, line_no);
      if (!numbers->empty()) return true;
    }
    return false;
  };
  // Header: "OFF", optionally followed on the same line by the counts.
  std::string first;
  while (first.empty() && std::getline(in, line)) {
    ++line_no;
    first = line.substr(0, line.find('#'));
    first.erase(0, first.find_first_not_of(" \t\r"));
  }
  if (first.rfind("OFF", 0) != 0) throw FileError(path, "not an OFF file (first line is not 'OFF')");
  std::vector<double> counts = OffNumbers(path, first.substr(3), line_no);
  if (counts.empty() && !next(&counts)) throw FileError(path, "truncated: no vertex/face counts");
  if (counts.size() < 2 || counts[0] < 0 || counts[1] < 0 || counts[0] != std::floor(counts[0]) ||
      counts[1] != std::floor(counts[1]) || counts[0] > std::numeric_limits<std::uint32_t>::max()) {
    throw FileError(path,
                    "line " + std::to_string(line_no) + ": bad counts (expected 'vertices faces edges')");
  }
  const auto num_vertices = static_cast<size_t>(counts[0]);
  const auto num_faces = static_cast<size_t>(counts[1]);
  Mesh mesh;
  std::vector<double> numbers;
  for (size_t i = 0; i < num_vertices; ++i) {
    if (!next(&numbers)) {
      throw FileError(
          path, "truncated: " + std::to_string(i) + " of " + std::to_string(num_vertices) + " vertices");
    }
    if (numbers.size() < 3) {
      throw FileError(path, "line " + std::to_string(line_no) + ": a vertex needs 3 coordinates");
    }
    mesh.vertices.emplace_back(numbers[0], numbers[1], numbers[2]);
  }
  for (size_t i = 0; i < num_faces; ++i) {
    if (!next(&numbers)) {
      throw FileError(path,
                      "truncated: " + std::to_string(i) + " of " + std::to_string(num_faces) + " faces");
    }
    const double n = numbers[0];
    if (n != std::floor(n) || n < 0 || numbers.size() < static_cast<size_t>(n) + 1) {
      throw FileError(path, "line " + std::to_string(line_no) + ": face has fewer indices than its count");
    }
    const std::vector<double> poly(numbers.begin() + 1, numbers.begin() + 1 + static_cast<size_t>(n));
    AddPolygon(path, "face", i, poly, num_vertices, &mesh.triangles);
  }
  if (in.bad()) throw FileError(path, "read error");
  return mesh;
}

Mesh ReadMesh(const std::filesystem::path& path) {
  return path.extension() == ".off" ? ReadMeshOff(path) : ReadMeshPly(path);
}

// --- PLY point cloud
// ----------------------------------------------------------------------------------------

void WriteCloudPly(const std::filesystem::path& path, const LabelledCloud& cloud, PlyEncoding encoding,
                   bool double_precision) {
  cloud.AssertConsistent();
  const bool colors = !cloud.colors_rgb.empty();
  const bool labels = !cloud.labels.empty();
  const bool cams = !cloud.camera_index.empty();
  const bool conf = !cloud.confidence.empty();
  const bool pixels = !cloud.pixels_px.empty();
  const bool frame_ids = !cloud.camera_frame_ids.empty();
  for (auto id : cloud.camera_frame_ids) {
    if (id < std::numeric_limits<std::int32_t>::min() || id > std::numeric_limits<std::int32_t>::max()) {
      throw FileError(path, "camera frame id " + std::to_string(id) + " does not fit a PLY int");
    }
  }
  std::ostringstream h;
  const char* coord = double_precision ? "double" : "float";
  h << HeaderStart(encoding) << "element vertex " << cloud.size() << "\n";
  h << "property " << coord << " x\nproperty " << coord << " y\nproperty " << coord << " z\n";
  if (colors) h << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (labels) h << "property uchar label\n";
  if (cams) h << "property uint camera_index\n";
  if (conf) h << "property float confidence\n";
  if (pixels) h << "property float pixel_u\nproperty float pixel_v\n";
  // The observing cameras as their own element (readers that do not know it skip it).
  if (!cloud.camera_centers_world.empty()) {
    h << "element camera " << cloud.camera_centers_world.size() << "\n";
    h << "property double x\nproperty double y\nproperty double z\n";
    if (frame_ids) h << "property int frame_id\n";
  }
  h << "end_header\n";

  PlyOut out(path, encoding);
  out.Text(h.str());
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (double_precision) {
      PutXyz<double>(out, cloud.positions_world[i]);
    } else {
      PutXyz<float>(out, cloud.positions_world[i]);
    }
    if (colors) PutRgb(out, cloud.colors_rgb[i]);
    if (labels) out.Value(cloud.labels[i]);
    if (cams) out.Value(cloud.camera_index[i]);
    if (conf) out.Value(cloud.confidence[i]);
    if (pixels) {
      out.Value(cloud.pixels_px[i].x());
      out.Value(cloud.pixels_px[i].y());
    }
    out.EndRow();
  }
  for (size_t c = 0; c < cloud.camera_centers_world.size(); ++c) {
    PutXyz<double>(out, cloud.camera_centers_world[c]);
    if (frame_ids) out.Value(static_cast<std::int32_t>(cloud.camera_frame_ids[c]));
    out.EndRow();
  }
  out.Close();
}

LabelledCloud ReadCloudPly(const std::filesystem::path& path) {
  const PlyTable table = mesh_internal::ReadPlyTable(path);
  const PlyElement& v = RequireElement(path, table, "vertex");
  LabelledCloud cloud;
  cloud.positions_world = ReadXyz(path, v);
  cloud.colors_rgb = ReadRgb(v);
  cloud.labels = ReadLabels(path, v);
  if (const PlyElement* cam = table.Find("camera")) {
    cloud.camera_centers_world = ReadXyz(path, *cam);
    if (const PlyProperty* ids = Optional(*cam, "frame_id")) {
      for (double id : ids->values) cloud.camera_frame_ids.push_back(static_cast<std::int64_t>(id));
    }
  }
  if (const PlyProperty* ci = Optional(v, "camera_index")) {
    const size_t num_cameras = cloud.camera_centers_world.size();
    cloud.camera_index.reserve(v.count);
    for (size_t i = 0; i < v.count; ++i) {
      const double c = ci->values[i];
      if (c < 0 || c >= static_cast<double>(num_cameras)) {
        throw FileError(path, "vertex " + std::to_string(i) + " has camera_index " + std::to_string(c) +
                                  " but the file has " + std::to_string(num_cameras) + " cameras");
      }
      cloud.camera_index.push_back(static_cast<std::uint32_t>(c));
    }
  }
  if (const PlyProperty* conf = Optional(v, "confidence")) {
    cloud.confidence.assign(conf->values.begin(), conf->values.end());
  }
  const PlyProperty* u = Optional(v, "pixel_u");
  const PlyProperty* pv = Optional(v, "pixel_v");
  if (u != nullptr && pv != nullptr) {
    cloud.pixels_px.resize(v.count);
    for (size_t i = 0; i < v.count; ++i) {
      cloud.pixels_px[i] = {static_cast<float>(u->values[i]), static_cast<float>(pv->values[i])};
    }
  }
  return cloud;
}

}  // namespace semap::io
