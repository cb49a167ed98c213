// Fuzzes the PLY (mesh and cloud) and OFF readers.
#include "io/mesh/ply_off.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  const auto ply = fuzz::WriteInput("input.ply", data, size);
  const auto off = fuzz::WriteInput("input.off", data, size);
  try {
    const Mesh m = io::ReadMeshPly(ply);
    if (!m.IsConsistent()) __builtin_trap();  // a reader must never return an inconsistent mesh
  } catch (const std::exception&) {
  }
  try {
    io::ReadCloudPly(ply).AssertConsistent();
  } catch (const std::exception&) {
  }
  try {
    const Mesh m = io::ReadMeshOff(off);
    if (!m.IsConsistent()) __builtin_trap();
  } catch (const std::exception&) {
  }
  return 0;
}
