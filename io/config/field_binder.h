// Binds the fields of an options struct to YAML keys, once, so that loading, `--set` overrides and the
// documented default config all come from the same list.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace semap::io {

// One bound field: its key inside the section, a one-line doc, and how to read and write it.
struct BoundField {
  std::string key;
  std::string doc;
  std::function<void(const YAML::Node&)> load;  // throws std::runtime_error on a malformed value
  std::function<YAML::Node()> dump;
};

// Collects the fields of one options struct. Usage in a section's bind function:
//   b.Field("num_disparities", &o.num_disparities, "disparity search range in px (multiple of 16)");
//   b.Enum("mode", &o.mode, {{"sgbm", Mode::kSgbm}, {"3way", Mode::kThreeWay}}, "OpenCV SGBM mode");
class FieldBinder {
 public:
  template <typename T>
  void Field(std::string key, T* value, std::string doc) {
    fields_.push_back({std::move(key), std::move(doc), [value](const YAML::Node& n) { *value = n.as<T>(); },
                       [value]() { return YAML::Node(*value); }});
  }

  template <typename E>
  void Enum(std::string key, E* value, std::vector<std::pair<std::string, E>> names, std::string doc) {
    std::string choices;
    for (const auto& [name, e] : names) choices += (choices.empty() ? "" : "|") + name;
    doc += " [" + choices + "]";
    fields_.push_back({std::move(key), std::move(doc),
                       [value, names, choices](const YAML::Node& n) {
                         const auto s = n.as<std::string>();
                         for (const auto& [name, e] : names) {
                           if (name == s) {
                             *value = e;
                             return;
                           }
                         }
                         throw std::runtime_error("'" + s + "' is not one of " + choices);
                       },
                       [value, names]() {
                         for (const auto& [name, e] : names) {
                           if (e == *value) return YAML::Node(name);
                         }
                         return YAML::Node("?");
                       }});
  }

  const std::vector<BoundField>& fields() const { return fields_; }

 private:
  std::vector<BoundField> fields_;
};

// A config section: a name ("depth"), a doc line, the bound fields and the options struct's Check().
struct Section {
  std::string name;
  std::string doc;
  FieldBinder binder;
  std::function<void()> check;  // throws semap::InvalidOption
};

}  // namespace semap::io
