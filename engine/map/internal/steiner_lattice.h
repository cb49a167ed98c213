// Bounding Steiner points: a jittered cubic lattice around the data, grown (and shrunk) with it.
// CGAL-free; the map inserts/removes the lattice nodes it reports.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace semap::map_internal {

using LatticeKey = std::int64_t;

// Every point or camera "uses" the lattice cube containing it; a used cube requires the lattice nodes of the
// cubes within `margin` cubes of it. Node positions are the lattice positions plus a deterministic jitter
// (a hash of the node index, up to ±10 % of the spacing per axis) that avoids the cospherical configurations
// of a perfect lattice (slow exact predicates) while staying a pure function of the node index, so a batch
// and an incremental map built from the same data get the same Steiner points. Not thread-safe.
class SteinerLattice {
 public:
  SteinerLattice(double spacing_m, int margin_cubes);

  // Marks the cube of `p` used at `frame`; appends the nodes that this makes newly required.
  void Use(const Eigen::Vector3d& p, std::int64_t frame, std::vector<LatticeKey>* new_nodes);

  // Forgets the cubes last used before `oldest_frame`; appends the nodes no remaining cube requires.
  void Expire(std::int64_t oldest_frame, std::vector<LatticeKey>* released_nodes);

  Eigen::Vector3d Position(LatticeKey node) const;
  std::size_t num_nodes() const { return node_refs_.size(); }
  std::size_t num_cubes() const { return cube_last_frame_.size(); }

 private:
  LatticeKey CubeOf(const Eigen::Vector3d& p) const;

  double spacing_m_;
  int margin_;
  std::unordered_map<LatticeKey, std::int64_t> cube_last_frame_;
  std::unordered_map<LatticeKey, int> node_refs_;  // number of used cubes requiring the node
};

}  // namespace semap::map_internal
