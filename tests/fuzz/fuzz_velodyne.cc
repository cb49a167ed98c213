// Fuzzes the Velodyne .bin reader.
#include "io/kitti/velodyne.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = semap::fuzz::WriteInput("scan.bin", data, size);
  try {
    semap::io::ReadVelodyneBin(path);
  } catch (const std::exception&) {
  }
  return 0;
}
