// Geometric primitives appended to a Scene (each primitive owns its vertices). Not thread-safe.
#pragma once

#include <vector>

#include "engine/sim/internal/random.h"
#include "engine/sim/scene.h"

namespace semap::sim::sim_internal {

// The appearance shared by the triangles of one primitive.
struct Surface {
  Label label = label::kUnlabelled;
  Material material = Material::kPlaster;
  std::uint32_t object_id = 0;
};

class SceneBuilder {
 public:
  explicit SceneBuilder(Scene* scene);

  // A planar quad p0 p1 p2 p3 (in order around it), wound so that its normal points along `facing`.
  void AddQuad(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
               const Eigen::Vector3d& p3, const Eigen::Vector3d& facing, const Surface& s);
  // A box with the given centre, half extents along its own axes and yaw about z; `with_bottom` adds the
  // bottom face.
  void AddBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double yaw_rad, const Surface& s,
              bool with_bottom = false);
  // An upright (or, with `axis`, any direction) closed cylinder.
  void AddCylinder(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double length,
                   int sides, const Surface& s);
  // An irregular blob (tree crown, bush): an icosphere with radii `radii`, its radius modulated by noise of
  // relative amplitude `roughness`; `seed` varies the shape.
  void AddBlob(const Eigen::Vector3d& center, const Eigen::Vector3d& radii, int subdivisions,
               double roughness, std::uint64_t seed, const Surface& s);
  // A rounded box |x/a|^p + |y/b|^p + |z/c|^p = 1 (p = `exponent`), yawed about z.
  void AddRoundedBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double yaw_rad,
                     double exponent, int subdivisions, const Surface& s);

  std::uint32_t NewObjectId() { return next_object_id_++; }

 private:
  std::uint32_t AddVertex(const Eigen::Vector3d& p);
  void AddTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const Surface& s);
  // Unit icosphere of a subdivision level (cached per builder).
  const std::pair<std::vector<Eigen::Vector3d>, std::vector<std::array<std::uint32_t, 3>>>& Icosphere(
      int level);

  Scene* scene_;
  std::uint32_t next_object_id_ = 1;
  std::vector<std::pair<std::vector<Eigen::Vector3d>, std::vector<std::array<std::uint32_t, 3>>>> spheres_;
};

// Sorts the scene's triangles into square cells of side `chunk_size_m` in x and y (stable: deterministic)
// and fills scene->chunks, which the renderer culls by. Call once, after the last primitive.
void SortIntoChunks(Scene* scene, double chunk_size_m);

}  // namespace semap::sim::sim_internal
