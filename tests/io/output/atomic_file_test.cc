#include "io/atomic_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/file_error.h"
#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// The names in `dir` (to see that no temporary file is left).
std::vector<std::string> Names(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(AtomicFile, WritesTheFileUnderItsNameOnlyOnCommit) {
  const fs::path dir = test::TempDir();
  const fs::path path = dir / "summary.json";
  AtomicFile file(path);
  file.stream() << "{}\n";
  EXPECT_FALSE(fs::exists(path));
  file.Commit();
  EXPECT_EQ(test::ReadTextFile(path), "{}\n");
  EXPECT_EQ(Names(dir), std::vector<std::string>{"summary.json"});
}

TEST(AtomicFile, AnInterruptedWriteKeepsTheOldContentAndLeavesNoTemporaryFile) {
  const fs::path dir = test::TempDir();
  const fs::path path = dir / "mesh.off";
  test::WriteTextFile(path, "old\n");
  try {
    AtomicFile file(path);
    file.stream() << "half a mesh";
    throw std::runtime_error("interrupted");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(test::ReadTextFile(path), "old\n");
  EXPECT_EQ(Names(dir), std::vector<std::string>{"mesh.off"});
}

TEST(AtomicFile, AnUnwritablePathIsAnErrorNamingIt) {
  const fs::path path = "/proc/semap_test_x.json";
  try {
    WriteFileAtomically(path, "{}");
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, AFullDeviceIsAnErrorNotSilence) {
  // /dev/full is not a regular file: it is written in place (never renamed over) and the failed write is an
  // error naming it.
  ASSERT_TRUE(fs::exists("/dev/full"));
  try {
    WriteFileAtomically("/dev/full", std::string(1 << 16, 'x'));
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full: write failed"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(CheckWritableFolder, CreatesAMissingFolderAndRefusesAFile) {
  const fs::path dir = test::TempDir();
  CheckWritableFolder(dir / "a" / "b");
  EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
  EXPECT_TRUE(Names(dir / "a" / "b").empty());
  test::WriteTextFile(dir / "file", "x");
  EXPECT_THROW(CheckWritableFolder(dir / "file"), FileError);
  EXPECT_THROW(CheckWritableFolder(dir / "file" / "sub"), FileError);
}

}  // namespace
}  // namespace semap::io
