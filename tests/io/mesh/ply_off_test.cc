#include "io/mesh/ply_off.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "tests/common/test_data.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

Mesh MakeMesh() {
  Mesh m;
  m.vertices = {{0.0, 0.0, 0.0}, {1.25, -3.5e-3, 123.456789012345}, {-7.1, 2.2, 0.3}, {1e-7, 5e4, -2.0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 1}};
  m.colors_rgb = {{{255, 0, 0}}, {{0, 255, 0}}, {{0, 0, 255}}, {{12, 34, 56}}};
  m.labels = {1, 3, 9, 255};
  return m;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Runs `fn`, expects a FileError whose message names `path` and contains `problem`.
void ExpectFileError(const std::function<void()>& fn, const fs::path& path, const std::string& problem) {
  try {
    fn();
    ADD_FAILURE() << "no FileError for " << path;
  } catch (const FileError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << "expected '" << problem << "' in: " << msg;
    EXPECT_EQ(e.path(), path);
  }
}

void ExpectVerticesNear(const Mesh& expected, const Mesh& actual, bool exact) {
  ASSERT_EQ(expected.num_vertices(), actual.num_vertices());
  for (size_t i = 0; i < expected.num_vertices(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (exact) {
        EXPECT_EQ(actual.vertices[i][k], expected.vertices[i][k]) << "vertex " << i << " coord " << k;
      } else {
        EXPECT_EQ(static_cast<float>(actual.vertices[i][k]), static_cast<float>(expected.vertices[i][k]))
            << "vertex " << i << " coord " << k;
      }
    }
  }
}

struct PlyCase {
  PlyEncoding encoding;
  bool double_precision;
};

class MeshPlyRoundTrip : public ::testing::TestWithParam<PlyCase> {};

TEST_P(MeshPlyRoundTrip, KeepsEveryAttribute) {
  const Mesh m = MakeMesh();
  const fs::path path = semap::test::TempDir() / "mesh.ply";
  WriteMeshPly(path, m, GetParam().encoding, GetParam().double_precision);
  const Mesh r = ReadMeshPly(path);
  ExpectVerticesNear(m, r, GetParam().double_precision);
  EXPECT_EQ(r.triangles, m.triangles);
  EXPECT_EQ(r.colors_rgb, m.colors_rgb);
  EXPECT_EQ(r.labels, m.labels);
}

TEST_P(MeshPlyRoundTrip, AbsentAttributesStayAbsent) {
  Mesh m = MakeMesh();
  m.colors_rgb.clear();
  m.labels.clear();
  const fs::path path = semap::test::TempDir() / "plain.ply";
  WriteMeshPly(path, m, GetParam().encoding, GetParam().double_precision);
  const Mesh r = ReadMeshPly(path);
  EXPECT_EQ(r.num_vertices(), 4u);
  EXPECT_EQ(r.triangles, m.triangles);
  EXPECT_TRUE(r.colors_rgb.empty());
  EXPECT_TRUE(r.labels.empty());
}

INSTANTIATE_TEST_SUITE_P(Encodings, MeshPlyRoundTrip,
                         ::testing::Values(PlyCase{PlyEncoding::kBinaryLittleEndian, false},
                                           PlyCase{PlyEncoding::kBinaryLittleEndian, true},
                                           PlyCase{PlyEncoding::kAscii, false},
                                           PlyCase{PlyEncoding::kAscii, true}));

TEST(MeshPly, HeaderUsesStandardPropertyNames) {
  const fs::path path = semap::test::TempDir() / "mesh.ply";
  WriteMeshPly(path, MakeMesh(), PlyEncoding::kBinaryLittleEndian);
  const std::string text = ReadText(path);
  const std::string header = text.substr(0, text.find("end_header\n") + 11);
  EXPECT_EQ(
      header,
      "ply\nformat binary_little_endian 1.0\ncomment written by semap\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty uchar label\nelement face 3\nproperty list uchar int vertex_indices\n"
      "end_header\n");
  // 4 vertices × (3 floats + 4 bytes) + 3 faces × (1 + 3 ints).
  EXPECT_EQ(text.size(), header.size() + 4 * 16 + 3 * 13);
}

TEST(MeshPly, AsciiBodyIsReadable) {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1.5, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  const fs::path path = semap::test::TempDir() / "tri.ply";
  WriteMeshPly(path, m, PlyEncoding::kAscii);
  const std::string text = ReadText(path);
  EXPECT_EQ(text.substr(text.find("end_header\n") + 11), "0 0 0\n1.5 0 0\n0 1 0\n3 0 1 2\n");
}

TEST(MeshPly, ReadsForeignFilesWithQuadsAndOtherTypes) {
  // A file as another tool might write it: double coordinates, int colours as uchar, a quad, a comment.
  const fs::path path = semap::test::TempDir() / "foreign.ply";
  WriteText(
      path,
      "ply\r\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\nproperty double x\n"
      "property double y\nproperty double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 1\nproperty list uchar uint vertex_index\nend_header\n"
      "0 0 0 1 2 3\n1 0 0 4 5 6\n1 1 0 7 8 9\n0 1 0 10 11 12\n4 0 1 2 3\n");
  const Mesh r = ReadMeshPly(path);
  ASSERT_EQ(r.num_triangles(), 2u);
  EXPECT_EQ(r.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(r.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(r.colors_rgb[3], (std::array<std::uint8_t, 3>{10, 11, 12}));
  EXPECT_TRUE(r.labels.empty());
}

TEST(MeshOff, ExactTextAndSize) {
  Mesh m;
  m.vertices = {{0, 0, 0}, {1.5, 0, 0}, {0, -2, 0.25}};
  m.triangles = {{0, 1, 2}};
  const fs::path path = semap::test::TempDir() / "tri.off";
  WriteMeshOff(path, m);
  const std::string expected = "OFF\n3 1 0\n0 0 0\n1.5 0 0\n0 -2 0.25\n3 0 1 2\n";
  EXPECT_EQ(ReadText(path), expected);
  EXPECT_EQ(OffSizeBytes(m), expected.size());
}

TEST(MeshOff, RoundTripAndSizeEqualsFileSize) {
  const Mesh m = MakeMesh();
  const fs::path path = semap::test::TempDir() / "mesh.off";
  WriteMeshOff(path, m);
  EXPECT_EQ(fs::file_size(path), OffSizeBytes(m));
  const Mesh r = ReadMeshOff(path);
  ExpectVerticesNear(m, r, /*exact=*/false);
  EXPECT_EQ(r.triangles, m.triangles);
  EXPECT_TRUE(r.colors_rgb.empty());
  EXPECT_TRUE(r.labels.empty());
  EXPECT_EQ(OffSizeBytes(Mesh{}), std::string("OFF\n0 0 0\n").size());
}

TEST(MeshOff, ReadsCommentsCountsOnHeaderLineAndPolygons) {
  const fs::path path = semap::test::TempDir() / "quad.off";
  WriteText(path, "# a comment\nOFF 4 1 0\n\n0 0 0\n1 0 0  # x\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n");
  const Mesh r = ReadMeshOff(path);
  EXPECT_EQ(r.num_vertices(), 4u);
  ASSERT_EQ(r.num_triangles(), 2u);
  EXPECT_EQ(r.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
}

LabelledCloud MakeCloud() {
  LabelledCloud c;
  c.positions_world = {{1, 2, 3}, {-4.5, 0.125, 1e3}, {0.1, 0.2, 0.3}};
  c.colors_rgb = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}};
  c.labels = {0, 14, 3};
  c.pixels_px = {{10.5f, 20.25f}, {0.f, 374.f}, {1241.f, 3.f}};
  c.confidence = {0.5f, 1.0f, 0.125f};
  c.camera_index = {0, 1, 1};
  c.camera_centers_world = {{0, 0, 0}, {0.1, -0.2, 10.000001}};
  c.camera_frame_ids = {7, 8};
  return c;
}

class CloudPlyRoundTrip : public ::testing::TestWithParam<PlyCase> {};

TEST_P(CloudPlyRoundTrip, KeepsEveryAttribute) {
  const LabelledCloud c = MakeCloud();
  const fs::path path = semap::test::TempDir() / "cloud.ply";
  WriteCloudPly(path, c, GetParam().encoding, GetParam().double_precision);
  const LabelledCloud r = ReadCloudPly(path);
  ASSERT_EQ(r.size(), c.size());
  for (size_t i = 0; i < c.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double p = c.positions_world[i][k];
      EXPECT_EQ(r.positions_world[i][k], GetParam().double_precision ? p : static_cast<float>(p));
    }
  }
  EXPECT_EQ(r.colors_rgb, c.colors_rgb);
  EXPECT_EQ(r.labels, c.labels);
  EXPECT_EQ(r.pixels_px, c.pixels_px);
  EXPECT_EQ(r.confidence, c.confidence);
  EXPECT_EQ(r.camera_index, c.camera_index);
  EXPECT_EQ(r.camera_centers_world, c.camera_centers_world);
  EXPECT_EQ(r.camera_frame_ids, c.camera_frame_ids);
}

TEST_P(CloudPlyRoundTrip, PositionsOnly) {
  LabelledCloud c;
  c.positions_world = {{1, 2, 3}, {4, 5, 6}};
  const fs::path path = semap::test::TempDir() / "bare.ply";
  WriteCloudPly(path, c, GetParam().encoding, GetParam().double_precision);
  const LabelledCloud r = ReadCloudPly(path);
  EXPECT_EQ(r.positions_world, c.positions_world);
  EXPECT_TRUE(r.colors_rgb.empty() && r.labels.empty() && r.camera_index.empty() && r.confidence.empty() &&
              r.pixels_px.empty() && r.camera_centers_world.empty());
}

INSTANTIATE_TEST_SUITE_P(Encodings, CloudPlyRoundTrip,
                         ::testing::Values(PlyCase{PlyEncoding::kBinaryLittleEndian, false},
                                           PlyCase{PlyEncoding::kBinaryLittleEndian, true},
                                           PlyCase{PlyEncoding::kAscii, false},
                                           PlyCase{PlyEncoding::kAscii, true}));

// --- bad input
// ------------------------------------------------------------------------------------------------

TEST(MeshFilesBadInput, MissingFile) {
  const fs::path path = semap::test::TempDir() / "nope.ply";
  ExpectFileError([&] { ReadMeshPly(path); }, path, "file not found");
  ExpectFileError([&] { ReadMeshOff(path); }, path, "file not found");
  ExpectFileError([&] { ReadCloudPly(path); }, path, "file not found");
}

TEST(MeshFilesBadInput, UnwritablePath) {
  const fs::path path = semap::test::TempDir() / "no_such_dir" / "m.ply";
  ExpectFileError([&] { WriteMeshPly(path, MakeMesh()); }, path, "cannot open for writing");
  ExpectFileError([&] { WriteMeshOff(path, MakeMesh()); }, path, "cannot open for writing");
}

TEST(MeshFilesBadInput, TruncatedBinaryPly) {
  const fs::path dir = semap::test::TempDir();
  const fs::path full = dir / "full.ply";
  WriteMeshPly(full, MakeMesh());
  const std::string text = ReadText(full);
  // Cut inside the vertex data, inside the face data, and one byte short.
  for (size_t cut : {text.find("end_header\n") + 11 + 20, text.size() - 10, text.size() - 1}) {
    const fs::path path = dir / ("cut" + std::to_string(cut) + ".ply");
    WriteText(path, text.substr(0, cut));
    ExpectFileError([&] { ReadMeshPly(path); }, path, "truncated");
  }
  const fs::path header_only = dir / "header.ply";
  WriteText(header_only, text.substr(0, 40));
  ExpectFileError([&] { ReadMeshPly(header_only); }, header_only, "truncated PLY header");
}

TEST(MeshFilesBadInput, TruncatedAsciiPly) {
  const fs::path dir = semap::test::TempDir();
  const fs::path full = dir / "full.ply";
  WriteMeshPly(full, MakeMesh(), PlyEncoding::kAscii);
  const std::string text = ReadText(full);
  const fs::path path = dir / "cut.ply";
  WriteText(path, text.substr(0, text.size() - 8));
  ExpectFileError([&] { ReadMeshPly(path); }, path, "truncated in element 'face'");
}

TEST(MeshFilesBadInput, MalformedPly) {
  const fs::path dir = semap::test::TempDir();
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const fs::path not_ply = dir / "not.ply";
  WriteText(not_ply, "solid cube\nfacet normal 0 0 1\n");
  ExpectFileError([&] { ReadMeshPly(not_ply); }, not_ply, "not a PLY file");

  const fs::path bad_value = dir / "bad_value.ply";
  WriteText(bad_value, header + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n");
  ExpectFileError([&] { ReadMeshPly(bad_value); }, bad_value, "malformed value 'abc'");

  const fs::path bad_index = dir / "bad_index.ply";
  WriteText(bad_index, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  ExpectFileError([&] { ReadMeshPly(bad_index); }, bad_index, "refers to vertex 7");

  const fs::path big_endian = dir / "big_endian.ply";
  WriteText(big_endian, "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n");
  ExpectFileError([&] { ReadMeshPly(big_endian); }, big_endian, "unsupported encoding");

  const fs::path no_x = dir / "no_x.ply";
  WriteText(no_x, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n1\n");
  ExpectFileError([&] { ReadMeshPly(no_x); }, no_x, "no scalar property 'x'");

  const fs::path bad_type = dir / "bad_type.ply";
  WriteText(bad_type, "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n1\n");
  ExpectFileError([&] { ReadMeshPly(bad_type); }, bad_type, "unknown type 'quad'");

  // A huge count in a tiny binary file must fail cleanly, not allocate.
  const fs::path huge = dir / "huge.ply";
  WriteText(huge,
            "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
            "property float y\nproperty float z\nend_header\nabcd");
  ExpectFileError([&] { ReadMeshPly(huge); }, huge, "truncated");
}

TEST(MeshFilesBadInput, CloudCameraIndexOutOfRange) {
  const fs::path path = semap::test::TempDir() / "cloud.ply";
  WriteText(path,
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
            "property uint camera_index\nelement camera 1\nproperty double x\nproperty double y\n"
            "property double z\nend_header\n0 0 0 3\n0 0 0\n");
  ExpectFileError([&] { ReadCloudPly(path); }, path, "camera_index 3");
}

TEST(MeshFilesBadInput, MalformedOff) {
  const fs::path dir = semap::test::TempDir();
  const fs::path full = dir / "full.off";
  WriteMeshOff(full, MakeMesh());
  const std::string text = ReadText(full);

  const fs::path cut_vertices = dir / "cut_v.off";
  WriteText(cut_vertices, text.substr(0, text.find('\n', 15)));
  ExpectFileError([&] { ReadMeshOff(cut_vertices); }, cut_vertices, "truncated");

  const fs::path cut_faces = dir / "cut_f.off";
  WriteText(cut_faces, text.substr(0, text.rfind('\n', text.size() - 2) + 1));
  ExpectFileError([&] { ReadMeshOff(cut_faces); }, cut_faces, "truncated: 2 of 3 faces");

  const fs::path not_off = dir / "not.off";
  WriteText(not_off, "PLY\n3 1 0\n");
  ExpectFileError([&] { ReadMeshOff(not_off); }, not_off, "not an OFF file");

  const fs::path bad_number = dir / "bad_number.off";
  WriteText(bad_number, "OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n");
  ExpectFileError([&] { ReadMeshOff(bad_number); }, bad_number, "line 4: malformed number 'x'");

  const fs::path bad_index = dir / "bad_index.off";
  WriteText(bad_index, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  ExpectFileError([&] { ReadMeshOff(bad_index); }, bad_index, "refers to vertex 3");

  const fs::path bad_counts = dir / "bad_counts.off";
  WriteText(bad_counts, "OFF\n-3 1 0\n");
  ExpectFileError([&] { ReadMeshOff(bad_counts); }, bad_counts, "bad counts");
}

}  // namespace
}  // namespace semap::io
