#include "io/labels/class_map_yaml.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string ErrorOf(const fs::path& path) {
  try {
    LoadClassMap(path);
  } catch (const FileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ClassMapYaml, EmptyPathIsCityscapes) {
  const ClassMap m = LoadClassMap("");
  EXPECT_EQ(m.scheme(), "cityscapes");
  EXPECT_EQ(m.classes().size(), 20u);
}

TEST(ClassMapYaml, CityscapesRoundTrip) {
  const fs::path path = test::TempDir() / "cityscapes.yaml";
  SaveClassMap(path, ClassMap::Cityscapes());
  const ClassMap m = LoadClassMap(path);
  const ClassMap want = ClassMap::Cityscapes();
  EXPECT_EQ(m.scheme(), want.scheme());
  EXPECT_EQ(m.unlabelled_id(), want.unlabelled_id());
  ASSERT_EQ(m.classes().size(), want.classes().size());
  for (size_t i = 0; i < want.classes().size(); ++i) {
    EXPECT_EQ(m.classes()[i].id, want.classes()[i].id);
    EXPECT_EQ(m.classes()[i].name, want.classes()[i].name);
    EXPECT_EQ(m.classes()[i].color_rgb, want.classes()[i].color_rgb);
    EXPECT_EQ(m.classes()[i].role, want.classes()[i].role);
  }
}

TEST(ClassMapYaml, CustomScheme) {
  const fs::path path = test::TempDir() / "custom.yaml";
  Write(path,
        "scheme: my_ade20k_subset\nunlabelled_id: 255\nclasses:\n"
        "  - {id: 3, name: floor, color: [80, 50, 50], role: ground}\n"
        "  - {id: 0, name: wall, color: [120, 120, 120], role: wall}\n"
        "  - {id: 20, name: car, color: [0, 102, 200]}\n"
        "  - {id: 255, name: unknown}\n");
  const ClassMap m = LoadClassMap(path);
  EXPECT_EQ(m.scheme(), "my_ade20k_subset");
  EXPECT_EQ(m.unlabelled_id(), 255);
  EXPECT_EQ(m.Role(3), ClassRole::kGround);
  EXPECT_EQ(m.Role(0), ClassRole::kWall);
  EXPECT_EQ(m.Role(20), ClassRole::kKeep);
  EXPECT_EQ(m.Color(20), (std::array<std::uint8_t, 3>{0, 102, 200}));
  EXPECT_EQ(m.FindByName("CAR"), 20);
}

TEST(ClassMapYaml, BadFilesNameFileAndEntry) {
  const fs::path dir = test::TempDir();
  const fs::path p = dir / "map.yaml";
  const std::string head = "scheme: s\nunlabelled_id: 0\nclasses:\n  - {id: 0, name: none}\n";
  Write(p, head + "  - {id: 1, name: road, role: floor}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": classes[1].role: 'floor' is not one of ground|wall|keep");
  Write(p, head + "  - {id: 0, name: road}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": classes[1].id: duplicate id 0");
  Write(p, head + "  - {id: 300, name: road}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": classes[1].id: 300 is outside 0..255");
  Write(p, head + "  - {id: 1, name: None}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": classes[1].name: duplicate name 'None'");
  Write(p, head + "  - {id: 1, name: road, color: [1, 2]}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": classes[1].color: expected [r, g, b]");
  Write(p, head + "  - {id: 1, name: road, colour: [1, 2, 3]}\n");
  EXPECT_NE(ErrorOf(p).find("classes[1]: unknown key 'colour'"), std::string::npos);
  Write(p, "scheme: s\nunlabelled_id: 7\nclasses:\n  - {id: 0, name: none}\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": unlabelled_id: 7 is not the id of a class");
  Write(p, "scheme: s\nunlabelled_id: 0\n");
  EXPECT_EQ(ErrorOf(p), p.string() + ": missing or empty list 'classes'");
  Write(p, "scheme: [unclosed\n");
  EXPECT_NE(ErrorOf(p).find("not valid YAML"), std::string::npos);
  EXPECT_EQ(ErrorOf(dir / "none.yaml"), (dir / "none.yaml").string() + ": class map file not found");
}

}  // namespace
}  // namespace semap::io
