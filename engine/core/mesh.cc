#include "engine/core/mesh.h"

namespace semap {

bool Mesh::IsConsistent() const {
  const size_t n = vertices.size();
  if (!colors_rgb.empty() && colors_rgb.size() != n) return false;
  if (!labels.empty() && labels.size() != n) return false;
  for (const auto& t : triangles) {
    for (auto i : t) {
      if (i >= n) return false;
    }
  }
  return true;
}

}  // namespace semap
