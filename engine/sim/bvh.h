// Bounding-volume hierarchy over a Scene's triangles for exact ray casting (scanner, ground-truth checks).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/sim/scene.h"

namespace semap::sim {

struct RayHit {
  double t = 0.0;              // ray parameter: hit point = origin + t * direction
  std::uint32_t triangle = 0;  // index into the scene's triangles
};

// Binned-SAH BVH. Keeps a copy of the triangle corners, not a reference to the scene. Immutable after
// construction: Intersect() is thread-safe.
class TriangleBvh {
 public:
  explicit TriangleBvh(const Scene& scene);

  // The nearest hit with t in [t_min, t_max], if any. `direction` need not be unit length.
  std::optional<RayHit> Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                  double t_min, double t_max) const;

  size_t num_nodes() const { return nodes_.size(); }

 private:
  struct Node {
    std::array<float, 3> lo, hi;
    std::uint32_t first_or_right = 0;  // leaf: first triangle in order_; inner: index of the right child
    std::uint32_t count = 0;           // > 0 for leaves
  };
  struct Tri {
    Eigen::Vector3d v0, e1, e2;
  };

  std::uint32_t Build(std::uint32_t begin, std::uint32_t end, std::vector<Eigen::Vector3f>& centroids,
                      std::vector<std::array<Eigen::Vector3f, 2>>& boxes, int depth);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;  // triangle indices, grouped by leaf
  std::vector<Tri> tris_;             // in order_ order
};

}  // namespace semap::sim
