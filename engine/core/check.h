// Assertions for programmer errors and the exception type for user-facing option errors.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace semap {

// A user error in an options struct or config value: names the offending field.
// Thrown by every Options::Check(); the config loader prefixes the section ("depth.block_size: ...").
class InvalidOption : public std::invalid_argument {
 public:
  InvalidOption(std::string field, const std::string& message)
      : std::invalid_argument(field + ": " + message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

namespace core_internal {
[[noreturn]] void AssertionFailed(const char* expr, const char* file, int line, const std::string& msg);
}  // namespace core_internal

}  // namespace semap

// Programmer errors: always on (release too), abort with the location. Never used for bad user input.
#define SEMAP_ASSERT(cond, ...)                                                                   \
  do {                                                                                            \
    if (!(cond)) {                                                                                \
      std::ostringstream semap_assert_os_;                                                        \
      static_cast<void>(semap_assert_os_ __VA_OPT__(<<) __VA_ARGS__);                             \
      ::semap::core_internal::AssertionFailed(#cond, __FILE__, __LINE__, semap_assert_os_.str()); \
    }                                                                                             \
  } while (false)

// User errors in an options struct: throws semap::InvalidOption naming the field and the value.
#define SEMAP_CHECK_OPTION(cond, field, value, requirement)       \
  do {                                                            \
    if (!(cond)) {                                                \
      std::ostringstream semap_opt_os_;                           \
      semap_opt_os_ << requirement << " (got " << (value) << ")"; \
      throw ::semap::InvalidOption(field, semap_opt_os_.str());   \
    }                                                             \
  } while (false)
