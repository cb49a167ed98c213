// semap_check_manifold MESH.ply|MESH.off: the independent manifold checker (manifold_checker.h) on a written
// mesh; prints the counts of each defect and the first messages. Exit 0: manifold (with boundary); 1: not;
// 2: unreadable.
#include <exception>
#include <filesystem>
#include <iostream>

#include "io/mesh/ply_off.h"
#include "tests/engine/map/manifold_checker.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: semap_check_manifold MESH.ply|MESH.off\n";
    return 2;
  }
  const std::filesystem::path path = argv[1];
  semap::Mesh mesh;
  try {
    mesh = semap::io::ReadMesh(path);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  const semap::test::ManifoldReport r = semap::test::CheckManifold(mesh, /*allow_boundary=*/true);
  std::cout << path.string() << ": " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
            << " triangles, " << r.num_boundary_edges << " boundary edges; bad triangles "
            << r.num_bad_triangles << ", non-manifold edges " << r.num_nonmanifold_edges
            << ", misoriented edges " << r.num_misoriented_edges << ", non-manifold vertices "
            << r.num_nonmanifold_vertices << "\n"
            << r.Summary();
  return r.ok() ? 0 : 1;
}
