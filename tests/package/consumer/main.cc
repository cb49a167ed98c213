// The downstream consumer of tests/package: a wall of points seen by three cameras, mapped by the batch map
// of the installed semap::engine. Exits 0 when the mesh has triangles, and prints its size.
#include <cstdio>
#include <random>

#include "engine/core/labelled_cloud.h"
#include "engine/map/batch_map.h"
#include "engine/map/map_options.h"

int main() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  semap::LabelledCloud wall;
  for (int c = 0; c < 3; ++c) wall.camera_centers_world.push_back({c - 1.0, -5.0, 0.3 * c});
  for (int i = 0; i < 1000; ++i) {
    wall.positions_world.push_back({u(rng), 0.05 * u(rng), u(rng)});
    wall.camera_index.push_back(std::uint32_t(i % 3));
  }
  semap::MapOptions options;
  options.Check();
  const semap::BatchMapResult result = semap::BuildBatchMap(options, wall, {});
  std::printf("semap_consumer: %zu vertices, %zu triangles\n", result.mesh.vertices.size(),
              result.mesh.triangles.size());
  return result.mesh.triangles.empty() ? 1 : 0;
}
