// A triangle mesh with optional per-vertex colour and semantic label.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/class_map.h"

namespace semap {

struct Mesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from the free side
  std::vector<std::array<std::uint8_t, 3>> colors_rgb;  // empty or one per vertex
  std::vector<Label> labels;                            // empty or one per vertex

  size_t num_vertices() const { return vertices.size(); }
  size_t num_triangles() const { return triangles.size(); }
  // Sizes agree and every triangle index is in range.
  bool IsConsistent() const;
};

}  // namespace semap
