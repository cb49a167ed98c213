#include "engine/core/class_map.h"

#include <algorithm>
#include <cctype>

#include "engine/core/check.h"

namespace semap {

const char* ClassRoleName(ClassRole role) {
  switch (role) {
    case ClassRole::kKeep:
      return "keep";
    case ClassRole::kGround:
      return "ground";
    case ClassRole::kWall:
      return "wall";
  }
  return "?";
}

ClassMap::ClassMap(std::string scheme, std::vector<SemanticClass> classes, Label unlabelled_id)
    : scheme_(std::move(scheme)), classes_(std::move(classes)), unlabelled_id_(unlabelled_id) {
  lookup_.fill(-1);
  for (size_t i = 0; i < classes_.size(); ++i) {
    SEMAP_ASSERT(lookup_[classes_[i].id] < 0, "duplicate class id " << int(classes_[i].id));
    lookup_[classes_[i].id] = static_cast<int>(i);
  }
}

ClassMap ClassMap::Cityscapes() {
  // Index order and colours of ../shared/models/enet-cityscapes/enet-classes.txt and enet-colors.txt.
  using R = ClassRole;
  std::vector<SemanticClass> c = {
      {0, "Unlabeled", {0, 0, 0}, R::kKeep},        {1, "Road", {81, 0, 81}, R::kGround},
      {2, "Sidewalk", {244, 35, 232}, R::kGround},  {3, "Building", {70, 70, 70}, R::kWall},
      {4, "Wall", {102, 102, 156}, R::kWall},       {5, "Fence", {190, 153, 153}, R::kWall},
      {6, "Pole", {153, 153, 153}, R::kKeep},       {7, "TrafficLight", {250, 170, 30}, R::kKeep},
      {8, "TrafficSign", {220, 220, 0}, R::kKeep},  {9, "Vegetation", {107, 142, 35}, R::kKeep},
      {10, "Terrain", {152, 251, 152}, R::kGround}, {11, "Sky", {70, 130, 180}, R::kKeep},
      {12, "Person", {220, 20, 60}, R::kKeep},      {13, "Rider", {255, 0, 0}, R::kKeep},
      {14, "Car", {0, 0, 142}, R::kKeep},           {15, "Truck", {0, 0, 70}, R::kKeep},
      {16, "Bus", {0, 60, 100}, R::kKeep},          {17, "Train", {0, 80, 100}, R::kKeep},
      {18, "Motorcycle", {0, 0, 230}, R::kKeep},    {19, "Bicycle", {119, 11, 32}, R::kKeep},
  };
  return ClassMap("cityscapes", std::move(c), 0);
}

const SemanticClass& ClassMap::Get(Label id) const {
  SEMAP_ASSERT(Contains(id), "unknown label id " << int(id));
  return classes_[lookup_[id]];
}

std::array<std::uint8_t, 3> ClassMap::Color(Label id) const {
  return Contains(id) ? classes_[lookup_[id]].color_rgb : std::array<std::uint8_t, 3>{0, 0, 0};
}

int ClassMap::FindByName(const std::string& name) const {
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return std::tolower(ch); });
    return s;
  };
  const std::string key = lower(name);
  for (const auto& c : classes_) {
    if (lower(c.name) == key) return c.id;
  }
  return -1;
}

}  // namespace semap
