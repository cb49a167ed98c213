// How an options struct declares its fields, once: each field's default is its initialiser, and its config
// key, its meaning and its valid values are one entry of the struct's Describe():
//   int vote_window_frames = 8;
//   ...
//   template <typename Visitor>
//   void Describe(Visitor& v) {
//     v.Field("vote_window_frames", &vote_window_frames, "the views of this many last frames vote ...",
//             AtLeast(1));
//     v.Enum("visibility", &visibility, {{"depth", Visibility::kDepth}, {"rays", Visibility::kRays}}, "...");
//   }
//   void Check() const { CheckDeclaredRanges(*this); }
// app/config binds the entries to YAML keys and prints them with their defaults and ranges
// (`semap config --defaults`, config/default.yaml); CheckDeclaredRanges() tests every field against its
// declared range and throws InvalidOption naming the key ("vote_window_frames: must be >= 1 (got 0)").
// A requirement that ties fields together stays in Check(), naming its fields through the declaration:
//   if (max_depth_m <= min_depth_m) {
//     throw OptionError(*this, max_depth_m, "must be greater than " + KeyOf(*this, min_depth_m));
//   }
//
// A visitor has Field(key, T* value, text[, valid]) and Enum(key, E* value, {{name, E}, ...}, text); the
// entries pass string literals, so a visitor may take the key and text as std::string or std::string_view.
#pragma once

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/core/check.h"

namespace semap {

// A bound of a range, and how it is written: its shortest decimal form unless given ("1/3").
struct Bound {
  Bound(double value) : value(value) {}  // implicit: AtLeast(1), In(0, 1)
  Bound(double value, std::string text) : value(value), text(std::move(text)) {}
  double value;
  std::string text;  // empty: the shortest decimal form that reads back as `value`
};

// The valid values of a number (or of each element of a list of numbers): an interval, optionally only its
// odd values or the multiples of a number, optionally one special value outside it ("-1 (off)").
class Range {
 public:
  Range AtMost(Bound hi) const;  // hi included
  Range Below(Bound hi) const;   // hi excluded
  Range Odd() const;
  Range MultipleOf(int divisor) const;
  // `value` is valid too, and means `meaning`: AtLeast(0).Or(-1, "off") is ">= 0, or -1 (off)".
  Range Or(double value, std::string meaning) const;

  bool Admits(double value) const;
  // What a valid value is, after "must be ": ">= 1", "in [0, 1)", "odd and in [1, 11]", ">= 0, or -1 (off)".
  std::string Text() const;
  std::string Requirement() const { return "must be " + Text(); }

 private:
  friend Range AtLeast(Bound lo);
  friend Range Above(Bound lo);

  std::optional<Bound> lo_, hi_;
  bool lo_open_ = false;
  bool hi_open_ = false;
  bool odd_ = false;
  int divisor_ = 0;  // 0: any value of the interval
  std::optional<double> special_;
  std::string special_meaning_;
};

Range AtLeast(Bound lo);                                                // [lo, ∞)
Range Above(Bound lo);                                                  // (lo, ∞)
inline Range In(Bound lo, Bound hi) { return AtLeast(lo).AtMost(hi); }  // [lo, hi]

// The valid values of a string: any but the empty one.
struct NotEmpty {
  std::string Text() const { return "not empty"; }
  std::string Requirement() const { return "must not be empty"; }
};

// No range declared: any value of the field's type (for floating-point fields: any finite one).
struct AnyValue {
  std::string Text() const { return {}; }
};

// True for a list option (a std::vector): its range applies to each of its elements.
template <typename T>
inline constexpr bool kIsListOption = false;
template <typename T>
inline constexpr bool kIsListOption<std::vector<T>> = true;

namespace core_internal {

// A value as an error message shows it: numbers as a stream writes them, strings quoted.
template <typename T>
std::string Shown(const T& value) {
  if constexpr (std::is_convertible_v<const T&, std::string_view>) {
    std::string quoted(1, '\'');
    quoted.append(std::string_view(value)).push_back('\'');
    return quoted;
  } else {
    std::ostringstream os;
    if constexpr (std::is_enum_v<T>) {
      os << static_cast<long long>(value);
    } else if constexpr (kIsListOption<T>) {
      os << "[";
      for (std::size_t i = 0; i < value.size(); ++i) os << (i ? ", " : "") << value[i];
      os << "]";
    } else {
      os << value;
    }
    return os.str();
  }
}

inline InvalidOption RangeError(std::string_view key, const std::string& requirement,
                                const std::string& got) {
  return InvalidOption(std::string(key), requirement + " (got " + got + ")");
}

// One number against its field's range; non-finite numbers are refused whatever the range (no option
// means anything with them, and they pass comparisons written as ranges).
template <typename T, typename Valid>
void CheckNumber(std::string_view key, const T& value, const Valid& valid, const char* each) {
  static_assert(std::is_arithmetic_v<T>, "a range applies to numbers and lists of numbers");
  if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(value))
      throw RangeError(key, std::string(each) + "must be a finite number", Shown(value));
  }
  if constexpr (std::is_same_v<Valid, Range>) {
    if (!valid.Admits(static_cast<double>(value))) {
      throw RangeError(key, std::string(each) + valid.Requirement(), Shown(value));
    }
  }
}

// Describe() visitor: throws InvalidOption for the first field outside its declared range.
class DeclaredRangeCheck {
 public:
  template <typename T, typename Valid = AnyValue>
  void Field(std::string_view key, const T* value, std::string_view /*text*/, const Valid& valid = {}) {
    if constexpr (std::is_same_v<Valid, NotEmpty>) {
      if (value->empty()) throw RangeError(key, valid.Requirement(), Shown(*value));
    } else if constexpr (kIsListOption<T>) {
      for (const auto& element : *value) CheckNumber(key, element, valid, "each ");
    } else if constexpr (std::is_arithmetic_v<T>) {
      CheckNumber(key, *value, valid, "");
    } else {
      static_assert(std::is_same_v<Valid, AnyValue>, "no range for this type of field");
    }
  }
  template <typename E>
  void Enum(std::string_view, const E*, const std::vector<std::pair<std::string, E>>&, std::string_view) {}
};

// Describe() visitor: the key of the member at one address.
template <typename Member>
class KeyFinder {
 public:
  explicit KeyFinder(const Member* member) : member_(member) {}
  template <typename T, typename Valid = AnyValue>
  void Field(std::string_view key, const T* value, std::string_view, const Valid& = {}) {
    Find(key, value);
  }
  template <typename E>
  void Enum(std::string_view key, const E* value, const std::vector<std::pair<std::string, E>>&,
            std::string_view) {
    Find(key, value);
  }
  const std::string& key() const { return key_; }

 private:
  template <typename T>
  void Find(std::string_view key, const T* value) {
    if constexpr (std::is_same_v<T, Member>) {
      if (value == member_) key_ = key;
    }
  }
  const Member* member_;
  std::string key_;
};

// Describe() only takes its fields' addresses, and these visitors only read through them: a const options
// struct can be described.
template <typename Options, typename Visitor>
void DescribeConst(const Options& options, Visitor& visitor) {
  const_cast<Options&>(options).Describe(visitor);
}

}  // namespace core_internal

// Throws InvalidOption naming the key of the first field (in Describe()'s order) whose value is outside the
// range its entry declares, or is not a finite number.
template <typename Options>
void CheckDeclaredRanges(const Options& options) {
  core_internal::DeclaredRangeCheck check;
  core_internal::DescribeConst(options, check);
}

// The key that `options`' Describe() declares for `member`, one of its fields.
template <typename Options, typename T>
std::string KeyOf(const Options& options, const T& member) {
  core_internal::KeyFinder<T> finder(&member);
  core_internal::DescribeConst(options, finder);
  SEMAP_ASSERT(!finder.key().empty(), "KeyOf: not a field that Describe() declares");
  return finder.key();
}

// The error of `member` (a field of `options`) failing a requirement its declared range cannot say, named by
// its key: "<key>: <requirement> (got <value>)".
template <typename Options, typename T>
InvalidOption OptionError(const Options& options, const T& member, const std::string& requirement) {
  return core_internal::RangeError(KeyOf(options, member), requirement, core_internal::Shown(member));
}
// The same, showing `got` (e.g. the offending element of a list) instead of the member's value.
template <typename Options, typename T, typename Got>
InvalidOption OptionError(const Options& options, const T& member, const std::string& requirement,
                          const Got& got) {
  return core_internal::RangeError(KeyOf(options, member), requirement, core_internal::Shown(got));
}

}  // namespace semap
