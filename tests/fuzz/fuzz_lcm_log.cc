// Fuzzes the LCM log reader and the mesh rebuilder (io/lcm): the input is read as an lcm-logger log (event
// headers, then the mesh block and index messages in it) and, whole, as one mesh_block_t and one mesh_end_t
// message fed to an assembler. A rebuilt mesh must be consistent with finite vertices.
#include <cstdlib>
#include <exception>

#include "io/lcm/lcm_log.h"
#include "io/lcm/mesh_blocks.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

void CheckMesh(const semap::Mesh& mesh) {
  if (!mesh.IsConsistent()) std::abort();
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  try {
    CheckMesh(io::ReplayMeshLog(fuzz::WriteInput("run.lcmlog", data, size)).mesh);
  } catch (const std::exception&) {
  }
  io::MeshBlockAssembler assembler;
  std::string error;
  if (auto block = io::DecodeMeshBlock(data, size, &error)) assembler.Add(*block);
  if (auto end = io::DecodeMeshEnd(data, size, &error)) assembler.Add(*end);
  CheckMesh(assembler.ToMesh());
  (void)assembler.Missing();
  return 0;
}
