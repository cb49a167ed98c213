// Fuzzes the line-based KITTI parsers: OXTS packets, raw timestamps, odometry times and poses.
#include "io/kitti/oxts.h"
#include "io/kitti/sequence_files.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  const auto path = fuzz::WriteInput("lines.txt", data, size);
  try {
    io::ParseOxtsLine(std::string(reinterpret_cast<const char*>(data), size), path);
  } catch (const std::exception&) {
  }
  try {
    io::ReadOxtsFile(path);
  } catch (const std::exception&) {
  }
  try {
    io::ReadKittiTimestamps(path);
  } catch (const std::exception&) {
  }
  try {
    io::ReadOdometryTimes(path);
  } catch (const std::exception&) {
  }
  try {
    io::ReadOdometryPoses(path, 3);
  } catch (const std::exception&) {
  }
  return 0;
}
