#include "io/kitti/velodyne.h"

#include <bit>
#include <cmath>
#include <fstream>

namespace semap::io {

static_assert(std::endian::native == std::endian::little, "Velodyne .bin files are little-endian");
static_assert(sizeof(Eigen::Vector4f) == 16, "one Velodyne record is 4 float32");

namespace {
constexpr std::uintmax_t kRecordBytes = 16;
}  // namespace

std::vector<Eigen::Vector4f> ReadVelodyneBin(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec)
    throw FileError(path, std::filesystem::exists(path) ? "cannot read size" : "Velodyne scan not found");
  if (bytes % kRecordBytes != 0) {
    throw FileError(path, "size " + std::to_string(bytes) +
                              " bytes is not a multiple of 16 (x, y, z, reflectance as float32): truncated?");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open for reading");
  std::vector<Eigen::Vector4f> points(bytes / kRecordBytes);
  in.read(reinterpret_cast<char*>(points.data()), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes)) throw FileError(path, "read error (short read)");
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].head<3>().allFinite()) {
      throw FileError(path, "point " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  return points;
}

void WriteVelodyneBin(const std::filesystem::path& path, const std::vector<Eigen::Vector4f>& points) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw FileError(path, "cannot open for writing");
  out.write(reinterpret_cast<const char*>(points.data()),
            static_cast<std::streamsize>(points.size() * sizeof(Eigen::Vector4f)));
  out.close();
  if (!out) throw FileError(path, "write failed");
}

}  // namespace semap::io
