#include "io/kitti/velodyne.h"

#include <gtest/gtest.h>

#include "tests/common/test_data.h"
#include "tests/io/kitti/tiny_kitti.h"

namespace semap::io {
namespace {

TEST(Velodyne, RoundTrip) {
  const auto path = test::TempDir() / "scan.bin";
  const std::vector<Eigen::Vector4f> pts = {{1.f, 2.f, 3.f, 0.5f}, {-4.f, 5.5f, -6.f, 0.f}};
  WriteVelodyneBin(path, pts);
  EXPECT_EQ(std::filesystem::file_size(path), 32u);
  EXPECT_EQ(ReadVelodyneBin(path), pts);
}

TEST(Velodyne, EmptyScanIsValid) {
  const auto path = test::TempDir() / "empty.bin";
  WriteVelodyneBin(path, {});
  EXPECT_TRUE(ReadVelodyneBin(path).empty());
}

TEST(Velodyne, SizeNotMultipleOf16) {
  const auto path = test::TempDir() / "bad.bin";
  test::WriteTextFile(path, std::string(36, '\0'));
  try {
    ReadVelodyneBin(path);
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() +
                                         ": size 36 bytes is not a multiple of 16 (x, y, z, reflectance as "
                                         "float32): truncated?");
  }
}

TEST(Velodyne, MissingFileAndNonFinite) {
  const auto dir = test::TempDir();
  EXPECT_THROW(ReadVelodyneBin(dir / "none.bin"), FileError);
  const float nan_point[4] = {1.f, std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f};
  test::WriteTextFile(dir / "nan.bin", std::string(reinterpret_cast<const char*>(nan_point), 16));
  EXPECT_THROW(ReadVelodyneBin(dir / "nan.bin"), FileError);
}

}  // namespace
}  // namespace semap::io
