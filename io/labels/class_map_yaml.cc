#include "io/labels/class_map_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>

namespace semap::io {
namespace {

constexpr int kMaxLabelId = 255;
constexpr int kMaxColorValue = 255;

int ReadInt(const YAML::Node& node, const std::string& where, const std::filesystem::path& path, int lo,
            int hi) {
  if (!node || !node.IsScalar()) throw FileError(path, where + ": missing or not a number");
  int v = 0;
  try {
    v = node.as<int>();
  } catch (const YAML::Exception&) {
    throw FileError(path, where + ": '" + node.as<std::string>() + "' is not an integer");
  }
  if (v < lo || v > hi) {
    throw FileError(path, where + ": " + std::to_string(v) + " is outside " + std::to_string(lo) + ".." +
                              std::to_string(hi));
  }
  return v;
}

ClassRole ParseRole(const YAML::Node& node, const std::string& where, const std::filesystem::path& path) {
  if (!node) return ClassRole::kKeep;
  const std::string s = node.as<std::string>();
  for (ClassRole r : {ClassRole::kGround, ClassRole::kWall, ClassRole::kKeep}) {
    if (s == ClassRoleName(r)) return r;
  }
  throw FileError(path, where + ": '" + s + "' is not one of ground|wall|keep");
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

ClassMap LoadClassMap(const std::filesystem::path& path) {
  if (path.empty()) return ClassMap::Cityscapes();
  if (!std::filesystem::exists(path)) throw FileError(path, "class map file not found");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    throw FileError(path, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap())
    throw FileError(path, "a class map must be a YAML map with scheme, unlabelled_id, classes");
  for (const auto& kv : root) {
    const auto key = kv.first.as<std::string>();
    if (key != "scheme" && key != "unlabelled_id" && key != "classes") {
      throw FileError(path, "unknown key '" + key + "' (expected scheme, unlabelled_id, classes)");
    }
  }
  if (!root["scheme"] || !root["scheme"].IsScalar()) throw FileError(path, "missing key 'scheme'");
  const std::string scheme = root["scheme"].as<std::string>();
  const YAML::Node classes = root["classes"];
  if (!classes || !classes.IsSequence() || classes.size() == 0) {
    throw FileError(path, "missing or empty list 'classes'");
  }
  std::vector<SemanticClass> out;
  std::set<int> ids;
  std::set<std::string> names;
  for (size_t i = 0; i < classes.size(); ++i) {
    const YAML::Node c = classes[i];
    const std::string where = "classes[" + std::to_string(i) + "]";
    if (!c.IsMap()) throw FileError(path, where + ": expected a map {id, name, color, role}");
    for (const auto& kv : c) {
      const auto key = kv.first.as<std::string>();
      if (key != "id" && key != "name" && key != "color" && key != "role") {
        throw FileError(path, where + ": unknown key '" + key + "' (expected id, name, color, role)");
      }
    }
    SemanticClass sc;
    sc.id = static_cast<Label>(ReadInt(c["id"], where + ".id", path, 0, kMaxLabelId));
    if (!ids.insert(sc.id).second)
      throw FileError(path, where + ".id: duplicate id " + std::to_string(sc.id));
    if (!c["name"] || !c["name"].IsScalar() || c["name"].as<std::string>().empty()) {
      throw FileError(path, where + ".name: missing");
    }
    sc.name = c["name"].as<std::string>();
    if (!names.insert(Lower(sc.name)).second)
      throw FileError(path, where + ".name: duplicate name '" + sc.name + "'");
    const YAML::Node color = c["color"];
    if (color) {
      if (!color.IsSequence() || color.size() != 3)
        throw FileError(path, where + ".color: expected [r, g, b]");
      for (int k = 0; k < 3; ++k) {
        sc.color_rgb[k] = static_cast<std::uint8_t>(
            ReadInt(color[k], where + ".color[" + std::to_string(k) + "]", path, 0, kMaxColorValue));
      }
    }
    sc.role = ParseRole(c["role"], where + ".role", path);
    out.push_back(std::move(sc));
  }
  const int unlabelled = ReadInt(root["unlabelled_id"], "unlabelled_id", path, 0, kMaxLabelId);
  if (!ids.count(unlabelled)) {
    throw FileError(path, "unlabelled_id: " + std::to_string(unlabelled) + " is not the id of a class");
  }
  return ClassMap(scheme, std::move(out), static_cast<Label>(unlabelled));
}

void SaveClassMap(const std::filesystem::path& path, const ClassMap& map) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "scheme" << YAML::Value << map.scheme();
  e << YAML::Key << "unlabelled_id" << YAML::Value << static_cast<int>(map.unlabelled_id());
  e << YAML::Key << "classes" << YAML::Value << YAML::BeginSeq;
  for (const auto& c : map.classes()) {
    e << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "id" << YAML::Value << static_cast<int>(c.id);
    e << YAML::Key << "name" << YAML::Value << c.name;
    e << YAML::Key << "color" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << static_cast<int>(c.color_rgb[0]) << static_cast<int>(c.color_rgb[1])
      << static_cast<int>(c.color_rgb[2]) << YAML::EndSeq;
    e << YAML::Key << "role" << YAML::Value << ClassRoleName(c.role);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq << YAML::EndMap;
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw FileError(path, "cannot open for writing");
  out << "# semap class map: ids of the label images, display colours, simplification roles\n"
      << e.c_str() << "\n";
  out.close();
  if (!out) throw FileError(path, "write failed");
}

}  // namespace semap::io
