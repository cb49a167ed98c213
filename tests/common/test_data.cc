#include "tests/common/test_data.h"

#include <cstdlib>

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

std::filesystem::path TempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "semap_test";
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (auto& ch : name) {
    if (ch == '/') ch = '_';
  }
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace semap::test
