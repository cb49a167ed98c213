// Where tests find their data, and the rule for the real data in ../shared:
// under CI (CI=true) a missing ../shared is a failure; elsewhere the test is skipped with a message.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace semap::test {

// ../shared, or $SEMAP_SHARED when set.
std::filesystem::path SharedDir();
// The project's source tree (config/, tests/data/).
std::filesystem::path SourceDir();
// True when running under CI (environment variable CI=true).
bool UnderCi();
// This test process's scratch folder under the system's temp directory (semap_test_<pid>), made on first use
// and removed with everything in it when the process exits (kept when SEMAP_KEEP_TEST_DIRS is set). Two
// suites running at once never share a folder.
const std::filesystem::path& ProcessTempRoot();
// A fresh, empty folder for the current test inside ProcessTempRoot() (emptied again on each call).
std::filesystem::path TempDir();
// The whole content of a file, byte for byte ("" when it cannot be read): a log, a report, a written mesh.
std::string ReadFile(const std::filesystem::path& path);
// A text file's non-empty lines (none when it cannot be read): frames.csv's rows, errors.jsonl's records.
std::vector<std::string> NonEmptyLines(const std::filesystem::path& path);
// The comma-separated cells of a CSV line without quoting (frames.csv's), empty ones included.
std::vector<std::string> CsvCells(const std::string& line);

}  // namespace semap::test

// Use at the start of a test that needs `relative` under ../shared.
#define SEMAP_REQUIRE_SHARED(relative)                                                           \
  do {                                                                                           \
    const auto semap_req_path_ = ::semap::test::SharedDir() / (relative);                        \
    if (!std::filesystem::exists(semap_req_path_)) {                                             \
      if (::semap::test::UnderCi()) {                                                            \
        FAIL() << "shared data missing under CI: " << semap_req_path_;                           \
      } else {                                                                                   \
        GTEST_SKIP() << "shared data not found at " << semap_req_path_ << " (set SEMAP_SHARED)"; \
      }                                                                                          \
    }                                                                                            \
  } while (false)
