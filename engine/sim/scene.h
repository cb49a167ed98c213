// The procedural street world: labelled, textured triangles in the scene frame (x east-ish, z up, road z =
// 0).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/class_map.h"
#include "engine/core/mesh.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

class Trajectory;

// Surface appearance of a triangle (the texture function used by the renderer).
enum class Material : std::uint8_t {
  kAsphalt,
  kPaving,  // sidewalk tiles
  kCurb,    // curb stones
  kBrick,
  kPlaster,
  kGlass,  // window panes
  kWood,   // doors, fence boards
  kRoof,
  kLeaves,
  kBark,
  kGrass,
  kCarPaint,
  kTyre,
  kMetal,  // poles
  kSign,
  kCount
};

// Cityscapes 20-class ids used by the generator (engine/core/class_map.h ClassMap::Cityscapes()).
namespace label {
inline constexpr Label kUnlabelled = 0, kRoad = 1, kSidewalk = 2, kBuilding = 3, kWall = 4, kFence = 5,
                       kPole = 6, kTrafficSign = 8, kVegetation = 9, kTerrain = 10, kSky = 11, kCar = 14;
}  // namespace label

// A group of spatially close triangles [first, first + count) with their bounding box (for culling).
struct SceneChunk {
  Eigen::AlignedBox3d box;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

// Triangle soup with per-triangle label, material and object id. Every vertex belongs to triangles of one
// object only, so per-vertex labels are exact. Immutable after BuildScene(); thread-safe to read.
struct Scene {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Eigen::Vector3f> normals;   // unit face normals (winding order)
  std::vector<Label> labels;              // Cityscapes id per triangle
  std::vector<Material> materials;        // per triangle
  std::vector<std::uint32_t> object_ids;  // per triangle: objects vary their colour by it
  std::vector<SceneChunk> chunks;         // triangles are sorted by chunk

  size_t num_triangles() const { return triangles.size(); }
  // The scene as a mesh in the frame `out_from_scene`, with per-vertex labels (and no colours).
  Mesh ToMesh(const Pose3d& out_from_scene) const;
};

// Builds the world around the drive: streets of a grid city, blocks with sidewalks and curbs, buildings with
// window/door relief, fences, trees, bushes, parked cars, poles and signs, composed by options.preset.
// Deterministic in (options, trajectory).
Scene BuildScene(const SynthOptions& options, const Trajectory& trajectory);

}  // namespace semap::sim
