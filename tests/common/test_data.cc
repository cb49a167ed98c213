#include "tests/common/test_data.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

namespace semap::test {

std::filesystem::path SharedDir() {
  if (const char* env = std::getenv("SEMAP_SHARED"); env && *env) return env;
  return SEMAP_DEFAULT_SHARED_DIR;
}

std::filesystem::path SourceDir() {
  if (const char* env = std::getenv("SEMAP_SOURCE_DIR"); env && *env) return env;
  return SEMAP_DEFAULT_SOURCE_DIR;
}

bool UnderCi() {
  const char* env = std::getenv("CI");
  return env && std::string(env) == "true";
}

namespace {

// Owns the process's scratch folder: removes it at exit.
class ProcessScratch {
 public:
  ProcessScratch()
      : root_(std::filesystem::temp_directory_path() / ("semap_test_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(root_);  // a folder left by an earlier process of the same pid
    std::filesystem::create_directories(root_);
  }
  ~ProcessScratch() {
    if (const char* keep = std::getenv("SEMAP_KEEP_TEST_DIRS"); keep && *keep) return;
    std::error_code ignored;  // nothing to report to at exit
    std::filesystem::remove_all(root_, ignored);
  }
  ProcessScratch(const ProcessScratch&) = delete;
  ProcessScratch& operator=(const ProcessScratch&) = delete;
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
};

}  // namespace

const std::filesystem::path& ProcessTempRoot() {
  static const ProcessScratch scratch;
  return scratch.root();
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::string> NonEmptyLines(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

std::vector<std::string> CsvCells(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

std::filesystem::path TempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "test";
  if (info) name = std::string(info->test_suite_name()) + "_" + info->name();
  for (auto& ch : name) {
    if (ch == '/') ch = '_';
  }
  const auto dir = ProcessTempRoot() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace semap::test
