#include "engine/core/check.h"

#include <cstdio>
#include <cstdlib>

namespace semap::core_internal {

void AssertionFailed(const char* expr, const char* file, int line, const std::string& msg) {
  std::fprintf(stderr, "semap: internal error: assertion '%s' failed at %s:%d %s\n", expr, file, line,
               msg.c_str());
  std::abort();
}

}  // namespace semap::core_internal
