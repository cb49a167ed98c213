// Where tests find their data, and the rule for the real data in ../shared:
// under CI (CI=true) a missing ../shared is a failure; elsewhere the test is skipped with a message.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace semap::test {

// ../shared, or $SEMAP_SHARED when set.
std::filesystem::path SharedDir();
// The project's source tree (config/, tests/data/).
std::filesystem::path SourceDir();
// True when running under CI (environment variable CI=true).
bool UnderCi();
// A fresh, empty temporary folder for the current test (removed at the start of the next run).
std::filesystem::path TempDir();

}  // namespace semap::test

// Use at the start of a test that needs `relative` under ../shared.
#define SEMAP_REQUIRE_SHARED(relative)                                                               \
  do {                                                                                               \
    const auto semap_req_path_ = ::semap::test::SharedDir() / (relative);                            \
    if (!std::filesystem::exists(semap_req_path_)) {                                                 \
      if (::semap::test::UnderCi()) {                                                                \
        FAIL() << "shared data missing under CI: " << semap_req_path_;                               \
      } else {                                                                                       \
        GTEST_SKIP() << "shared data not found at " << semap_req_path_ << " (set SEMAP_SHARED)";     \
      }                                                                                              \
    }                                                                                                \
  } while (false)
