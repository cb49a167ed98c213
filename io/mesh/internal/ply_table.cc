#include "io/mesh/internal/ply_table.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "io/file_error.h"

namespace semap::io::mesh_internal {
namespace {

static_assert(std::endian::native == std::endian::little, "the PLY reader assumes a little-endian host");

// A header longer than this is not a PLY header (protects against reading a huge non-PLY file as text).
constexpr int kMaxHeaderLines = 10000;
// Longest list a face may hold; longer counts are taken as corruption.
constexpr std::uint64_t kMaxListCount = 1u << 16;

bool ParseType(const std::string& s, PlyType* t) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [name, type] : kNames) {
    if (s == name) {
      *t = type;
      return true;
    }
  }
  return false;
}

size_t TypeBytes(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool IsInteger(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

template <typename T>
double Load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double LoadBinary(PlyType t, const char* p) {
  switch (t) {
    case PlyType::kInt8:
      return Load<std::int8_t>(p);
    case PlyType::kUint8:
      return Load<std::uint8_t>(p);
    case PlyType::kInt16:
      return Load<std::int16_t>(p);
    case PlyType::kUint16:
      return Load<std::uint16_t>(p);
    case PlyType::kInt32:
      return Load<std::int32_t>(p);
    case PlyType::kUint32:
      return Load<std::uint32_t>(p);
    case PlyType::kFloat32:
      return Load<float>(p);
    case PlyType::kFloat64:
      return Load<double>(p);
  }
  return 0.0;
}

// Reads the values after the header, either binary (a byte cursor) or ASCII (a token cursor).
class BodyReader {
 public:
  BodyReader(const std::filesystem::path& path, std::string body, bool binary)
      : path_(path), body_(std::move(body)), binary_(binary) {}

  double Read(PlyType type, const PlyElement& e, std::uint64_t row, const std::string& prop) {
    if (binary_) {
      const size_t n = TypeBytes(type);
      if (pos_ + n > body_.size()) Fail("truncated", e, row, prop);
      const double v = LoadBinary(type, body_.data() + pos_);
      pos_ += n;
      return v;
    }
    while (pos_ < body_.size() && std::isspace(static_cast<unsigned char>(body_[pos_]))) ++pos_;
    if (pos_ >= body_.size()) Fail("truncated", e, row, prop);
    size_t end = pos_;
    while (end < body_.size() && !std::isspace(static_cast<unsigned char>(body_[end]))) ++end;
    double v = 0.0;
    const char* first = body_.data() + pos_;
    const char* last = body_.data() + end;
    if (*first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (ec != std::errc() || ptr != last || !std::isfinite(v)) {
      Fail("malformed value '" + std::string(body_.data() + pos_, end - pos_) + "'", e, row, prop);
    }
    if (IsInteger(type) && v != std::floor(v)) {
      Fail("non-integer value '" + std::string(body_.data() + pos_, end - pos_) + "'", e, row, prop);
    }
    pos_ = end;
    // A float property holds float values: "0.3" is the float nearest 0.3, as a binary file would hold.
    return type == PlyType::kFloat32 ? static_cast<double>(static_cast<float>(v)) : v;
  }

  // Bytes left (binary) or characters left (ASCII): an upper bound on the values still to come.
  size_t remaining() const { return body_.size() - pos_; }

 private:
  [[noreturn]] void Fail(const std::string& problem, const PlyElement& e, std::uint64_t row,
                         const std::string& prop) const {
    std::ostringstream os;
    os << problem << " in element '" << e.name << "' row " << row << " of " << e.count << ", property '"
       << prop << "'";
    throw FileError(path_, os.str());
  }

  const std::filesystem::path& path_;
  std::string body_;
  bool binary_;
  size_t pos_ = 0;
};

std::vector<std::string> Split(const std::string& line) {
  std::istringstream is(line);
  return {std::istream_iterator<std::string>(is), std::istream_iterator<std::string>()};
}

// Parses the header lines; leaves `in` at the first byte of the body.
PlyTable ParseHeader(const std::filesystem::path& path, std::istream& in) {
  PlyTable table;
  std::string line;
  if (!std::getline(in, line)) throw FileError(path, "empty file, not a PLY file");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "ply") throw FileError(path, "not a PLY file (first line is not 'ply')");
  bool have_format = false;
  for (int n = 1; n < kMaxHeaderLines; ++n) {
    if (!std::getline(in, line)) throw FileError(path, "truncated PLY header (no end_header)");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (in.eof() && line != "end_header") throw FileError(path, "truncated PLY header (no end_header)");
    const auto tok = Split(line);
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    const auto bad = [&](const std::string& why) {
      return FileError(path, "PLY header line " + std::to_string(n + 1) + " '" + line + "': " + why);
    };
    if (tok[0] == "end_header") {
      if (!have_format) throw FileError(path, "PLY header has no format line");
      return table;
    }
    if (tok[0] == "format") {
      if (tok.size() != 3) throw bad("expected 'format <encoding> 1.0'");
      if (tok[1] == "ascii") {
        table.binary = false;
      } else if (tok[1] == "binary_little_endian") {
        table.binary = true;
      } else {
        throw bad("unsupported encoding (ascii and binary_little_endian are supported)");
      }
      have_format = true;
    } else if (tok[0] == "element") {
      if (tok.size() != 3) throw bad("expected 'element <name> <count>'");
      PlyElement e;
      e.name = tok[1];
      const auto [ptr, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
      if (ec != std::errc() || ptr != tok[2].data() + tok[2].size()) throw bad("bad element count");
      table.elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (table.elements.empty()) throw bad("property before any element");
      PlyProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        p.is_list = true;
        if (!ParseType(tok[2], &p.count_type) || !IsInteger(p.count_type)) throw bad("bad list count type");
        if (!ParseType(tok[3], &p.type)) throw bad("unknown type '" + tok[3] + "'");
        p.name = tok[4];
      } else if (tok.size() == 3) {
        if (!ParseType(tok[1], &p.type)) throw bad("unknown type '" + tok[1] + "'");
        p.name = tok[2];
      } else {
        throw bad("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      table.elements.back().properties.push_back(std::move(p));
    } else {
      throw bad("unknown keyword '" + tok[0] + "'");
    }
  }
  throw FileError(path, "PLY header too long (no end_header)");
}

}  // namespace

const PlyProperty* PlyElement::Find(const std::string& prop_name) const {
  for (const auto& p : properties) {
    if (p.name == prop_name) return &p;
  }
  return nullptr;
}

const PlyElement* PlyTable::Find(const std::string& element_name) const {
  for (const auto& e : elements) {
    if (e.name == element_name) return &e;
  }
  return nullptr;
}

PlyTable ReadPlyTable(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "file not found");
  }
  PlyTable table = ParseHeader(path, in);
  std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw FileError(path, "read error");
  BodyReader reader(path, std::move(body), table.binary);
  for (auto& e : table.elements) {
    // Every row takes at least one byte (binary) or two characters (ASCII) per property: a count larger
    // than what is left cannot be satisfied, so do not reserve memory for it.
    const std::uint64_t reserve = std::min<std::uint64_t>(e.count, reader.remaining());
    for (auto& p : e.properties) {
      p.values.reserve(p.is_list ? reserve * 3 : reserve);
      if (p.is_list) p.list_counts.reserve(reserve);
    }
    for (std::uint64_t row = 0; row < e.count; ++row) {
      for (auto& p : e.properties) {
        if (!p.is_list) {
          p.values.push_back(reader.Read(p.type, e, row, p.name));
          continue;
        }
        const double count = reader.Read(p.count_type, e, row, p.name);
        if (count < 0 || count > static_cast<double>(kMaxListCount)) {
          std::ostringstream os;
          os << "invalid list length " << count << " in element '" << e.name << "' row " << row
             << ", property '" << p.name << "'";
          throw FileError(path, os.str());
        }
        p.list_counts.push_back(static_cast<std::uint32_t>(count));
        for (std::uint32_t k = 0; k < p.list_counts.back(); ++k) {
          p.values.push_back(reader.Read(p.type, e, row, p.name));
        }
      }
    }
  }
  return table;
}

}  // namespace semap::io::mesh_internal
