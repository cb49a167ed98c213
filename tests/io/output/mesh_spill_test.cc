#include "io/output/mesh_spill.h"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "io/file_error.h"
#include "tests/common/test_data.h"

namespace semap::io {
namespace {

MeshDelta Triangles(TriangleId first, int n, bool colors) {
  MeshDelta d;
  for (int i = 0; i < n; ++i) {
    const VertexId v = 10 * (first + TriangleId(i));
    d.added_triangle_ids.push_back(first + TriangleId(i));
    d.added_triangles.push_back({v, v + 1, v + 2});
    for (VertexId k = v; k < v + 3; ++k) {
      d.vertex_ids.push_back(k);
      d.vertex_positions.emplace_back(double(k), 0.5 * double(k), -double(k));
      if (colors) d.vertex_colors_rgb.push_back({std::uint8_t(k), 2, 3});
      d.vertex_labels.push_back(Label(k % 19));
    }
  }
  return d;
}

void ExpectSame(const MeshDelta& a, const MeshDelta& b) {
  EXPECT_EQ(a.added_triangle_ids, b.added_triangle_ids);
  EXPECT_EQ(a.added_triangles, b.added_triangles);
  EXPECT_EQ(a.vertex_ids, b.vertex_ids);
  EXPECT_EQ(a.vertex_positions, b.vertex_positions);
  EXPECT_EQ(a.vertex_colors_rgb, b.vertex_colors_rgb);
  EXPECT_EQ(a.vertex_labels, b.vertex_labels);
}

TEST(MeshSpill, GivesBackWhatWasAppendedInOrderAndRemovesItsFile) {
  const auto path = test::TempDir() / "spill";
  const std::vector<MeshDelta> appended = {Triangles(1, 3, true), Triangles(4, 1, false),
                                           Triangles(9, 50, true)};
  {
    MeshSpill spill(path);
    EXPECT_FALSE(std::filesystem::exists(path));  // nothing yet
    spill.Append(MeshDelta{});                    // nothing to keep
    EXPECT_FALSE(std::filesystem::exists(path));
    for (const MeshDelta& d : appended) spill.Append(d);
    EXPECT_EQ(spill.num_triangles(), 54u);
    std::vector<MeshDelta> read;
    spill.ForEach([&](const MeshDelta& d) { read.push_back(d); });
    ASSERT_EQ(read.size(), appended.size());
    for (std::size_t i = 0; i < read.size(); ++i) ExpectSame(read[i], appended[i]);
    // Appending goes on after a read.
    spill.Append(Triangles(100, 2, true));
    std::size_t records = 0;
    spill.ForEach([&](const MeshDelta&) { ++records; });
    EXPECT_EQ(records, 4u);
    EXPECT_TRUE(std::filesystem::exists(path));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(MeshSpill, ATruncatedFileIsAnErrorNamingIt) {
  const auto path = test::TempDir() / "spill";
  MeshSpill spill(path);
  spill.Append(Triangles(1, 20, true));
  spill.ForEach([](const MeshDelta&) {});
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 10);
  try {
    spill.ForEach([](const MeshDelta&) {});
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(MeshSpill, AFolderThatCannotHoldItIsAnErrorNamingTheFile) {
  const auto path = test::TempDir() / "missing" / "spill";
  MeshSpill spill(path);
  try {
    spill.Append(Triangles(1, 1, false));
    FAIL() << "expected FileError";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  // Once failed, it stays failed (a later record could not follow a partial one).
  std::filesystem::create_directories(path.parent_path());
  EXPECT_THROW(spill.Append(Triangles(2, 1, false)), FileError);
  EXPECT_EQ(spill.num_triangles(), 0u);
}

}  // namespace
}  // namespace semap::io
