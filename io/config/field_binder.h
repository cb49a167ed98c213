// Binds the fields of an options struct to YAML keys, once, so that loading, `--set` overrides and the
// documented default config all come from the same list.
#pragma once

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/core/options.h"

namespace semap::io {

namespace config_internal {

// Non-finite numbers (.inf, .nan) are refused for every floating-point option: no parameter means anything
// with them, and they would pass range checks written as comparisons.
template <typename T>
void CheckFinite(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(value)) throw std::runtime_error("must be a finite number");
  }
}
template <typename T>
void CheckFinite(const std::vector<T>& values) {
  for (const T& v : values) CheckFinite(v);
}

// A value as YAML; floating-point numbers in their shortest form that reads back exactly (0.3, not
// 0.29999999999999999), whole numbers below 10^15 without an exponent (1000000, not 1e+06).
template <typename T>
YAML::Node Dump(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    constexpr T kLargestPlain = T(1e15);
    char buf[64];
    const bool whole = std::abs(value) < kLargestPlain && value == std::trunc(value);
    const auto [end, ec] = whole ? std::to_chars(buf, buf + sizeof(buf), value, std::chars_format::fixed)
                                 : std::to_chars(buf, buf + sizeof(buf), value);
    if (ec == std::errc()) return YAML::Node(std::string(buf, end));
  }
  return YAML::Node(value);
}
template <typename T>
YAML::Node Dump(const std::vector<T>& values) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const T& v : values) n.push_back(Dump(v));
  return n;
}

}  // namespace config_internal

// One bound field: its key inside the section, a one-line doc (its text, then its choices or valid range),
// the member it is bound to, and how to read and write it.
struct BoundField {
  std::string key;
  std::string doc;
  const void* member = nullptr;
  std::function<void(const YAML::Node&)> load;  // throws std::runtime_error on a malformed value
  std::function<YAML::Node()> dump;
};

// Collects the fields of one options struct: the visitor of its Describe() (engine/core/options.h).
// A field's doc is its text followed by its valid range ("...; must be >= 1"), an enum's by its choices.
class FieldBinder {
 public:
  template <typename T, typename Valid = AnyValue>
  void Field(std::string key, T* value, std::string doc, const Valid& valid = {}) {
    if constexpr (!std::is_same_v<Valid, AnyValue>) {
      doc += std::string("; ") + (kIsListOption<T> ? "each " : "") + valid.Requirement();
    }
    fields_.push_back({std::move(key), std::move(doc), value,
                       [value](const YAML::Node& n) {
                         T v = n.as<T>();
                         config_internal::CheckFinite(v);
                         *value = std::move(v);
                       },
                       [value]() { return config_internal::Dump(*value); }});
  }

  template <typename E>
  void Enum(std::string key, E* value, std::vector<std::pair<std::string, E>> names, std::string doc) {
    std::string choices;
    for (const auto& [name, e] : names) choices += (choices.empty() ? "" : "|") + name;
    doc += " [" + choices + "]";
    fields_.push_back({std::move(key), std::move(doc), value,
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
