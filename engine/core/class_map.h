// Semantic classes: which label ids exist, how they are drawn, and which are simplification targets.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace semap {

// A label id as stored per pixel and per point (the id scheme of the ClassMap in use).
using Label = std::uint8_t;

// What the simplifier does with a class. Ground and wall classes are simplified (each group gets its own
// RANSAC plane); every other class is kept untouched.
enum class ClassRole : std::uint8_t { kKeep, kGround, kWall };

const char* ClassRoleName(ClassRole role);

struct SemanticClass {
  Label id = 0;
  std::string name;
  std::array<std::uint8_t, 3> color_rgb{0, 0, 0};
  ClassRole role = ClassRole::kKeep;
};

// Maps label ids to names, display colours and roles. Not thread-safe to mutate; const methods are.
class ClassMap {
 public:
  ClassMap() = default;
  // `unlabelled_id` is the id given to points with no semantic information.
  ClassMap(std::string scheme, std::vector<SemanticClass> classes, Label unlabelled_id);

  // The Cityscapes 20-class scheme of the ENet model (ids 0..19, 0 = Unlabeled), ground = road, sidewalk,
  // terrain; walls = building, wall, fence (the paper's targets).
  static ClassMap Cityscapes();

  const std::string& scheme() const { return scheme_; }
  Label unlabelled_id() const { return unlabelled_id_; }
  const std::vector<SemanticClass>& classes() const { return classes_; }

  bool Contains(Label id) const { return lookup_[id] >= 0; }
  // Requires Contains(id).
  const SemanticClass& Get(Label id) const;
  // Role of a label; unknown ids are kKeep.
  ClassRole Role(Label id) const { return Contains(id) ? classes_[lookup_[id]].role : ClassRole::kKeep; }
  bool IsTarget(Label id) const { return Role(id) != ClassRole::kKeep; }
  // Display colour; unknown ids are black.
  std::array<std::uint8_t, 3> Color(Label id) const;
  // Id of the class with this name (case-insensitive), or -1.
  int FindByName(const std::string& name) const;

 private:
  std::string scheme_;
  std::vector<SemanticClass> classes_;
  std::array<int, 256> lookup_{};
  Label unlabelled_id_ = 0;
};

}  // namespace semap
