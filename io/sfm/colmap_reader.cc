// Reading COLMAP models (text and binary) into an SfmReconstruction: io/sfm/colmap.h.
#include <Eigen/Geometry>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_set>

#include "io/sfm/colmap.h"
#include "io/sfm/internal/camera_models.h"
#include "io/sfm/internal/sfm_checks.h"

namespace semap::io {

using namespace sfm_internal;

static_assert(std::endian::native == std::endian::little, "COLMAP .bin models are little-endian");

namespace {

constexpr std::uint64_t kBinaryNoPoint3D = UINT64_MAX;  // COLMAP's kInvalidPoint3DId (text: -1)

// A COLMAP model as read, before the cross-references are checked.
struct Image {
  std::string entry;  // for errors: "line 12 (IMAGE_ID 3)"
  SfmView view;
  std::vector<Eigen::Vector2d> xy;
  std::vector<std::int64_t> point3d;  // -1 = none
};
struct Point {
  std::size_t where = 0;  // line (text) or record number (binary)
  std::int64_t id = 0;
  Eigen::Vector3d xyz;
  std::array<std::uint8_t, 3> rgb{};
  std::vector<std::pair<std::int64_t, std::uint32_t>> track;  // (IMAGE_ID, POINT2D_IDX)
};
struct Model {
  ColmapEncoding encoding = ColmapEncoding::kText;
  std::filesystem::path cameras_file, images_file, points_file;
  std::vector<SfmIntrinsics> cameras;
  std::vector<Image> images;
  std::vector<Point> points;

  EntryRef PointRef(const Point& p) const {
    const std::string where = encoding == ColmapEncoding::kText ? "line " + std::to_string(p.where)
                                                                : "point #" + std::to_string(p.where);
    return {points_file, where + " (POINT3D_ID " + std::to_string(p.id) + ")"};
  }
};

const char* Extension(ColmapEncoding e) { return e == ColmapEncoding::kText ? ".txt" : ".bin"; }

// world_from_cam of COLMAP's cam_from_world (quaternion w x y z, translation).
Pose3d PoseFromColmap(const EntryRef& at, const double q[4], const double t[3]) {
  CheckFinite(at, "QW QX QY QZ", q, 4);
  CheckFinite(at, "TX TY TZ", t, 3);
  const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  const double norm = quat.norm();
  if (std::abs(norm - 1.0) > kQuaternionTolerance) {
    at.Fail("QW QX QY QZ", "not a unit quaternion (norm " + NumberText(norm) + ")");
  }
  Pose3d cam_from_world = Pose3d::Identity();
  cam_from_world.linear() = quat.normalized().toRotationMatrix();
  cam_from_world.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return cam_from_world.inverse(Eigen::Isometry);
}

void CheckModelParams(const EntryRef& at, const SfmIntrinsics& k) {
  const auto model = ColmapModelByName(k.model);
  if (!model) at.Fail("MODEL", "unknown camera model '" + k.model + "'");
  if (static_cast<int>(k.params.size()) != model->num_params) {
    at.Fail("PARAMS", k.model + " has " + std::to_string(model->num_params) + " parameters (got " +
                          std::to_string(k.params.size()) + ")");
  }
  CheckFinite(at, "PARAMS", k.params.data(), static_cast<int>(k.params.size()));
}

// ---------------------------------------------------------------------------------------------- text

std::ifstream OpenText(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "file not found");
  return in;
}

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

bool IsBlankOrComment(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

template <typename T>
T ParseInteger(std::string_view token, const EntryRef& at, const std::string& field) {
  T value{};
  const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size()) {
    at.Fail(field, "'" + std::string(token) + "' is not an integer in range");
  }
  return value;
}

double ParseReal(std::string_view token, const EntryRef& at, const std::string& field) {
  double value = 0.0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
  if (r.ec == std::errc::result_out_of_range) at.Fail(field, "'" + std::string(token) + "' is out of range");
  if (r.ec != std::errc() || r.ptr != token.data() + token.size()) {
    at.Fail(field, "'" + std::string(token) + "' is not a number");
  }
  return value;
}

void NeedTokens(const EntryRef& at, const std::vector<std::string_view>& t, std::size_t n,
                const char* fields) {
  if (t.size() < n) {
    at.Fail("", "expected " + std::string(fields) + " (" + std::to_string(n) + " values, got " +
                    std::to_string(t.size()) + ")");
  }
}

void ReadCamerasText(Model* m) {
  std::ifstream in = OpenText(m->cameras_file);
  std::string line;
  for (std::size_t line_no = 1; std::getline(in, line); ++line_no) {
    if (IsBlankOrComment(line)) continue;
    EntryRef at{m->cameras_file, "line " + std::to_string(line_no)};
    const auto t = Tokens(line);
    NeedTokens(at, t, 4, "CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
    SfmIntrinsics k;
    k.id = ParseInteger<std::uint32_t>(t[0], at, "CAMERA_ID");
    at.entry += " (CAMERA_ID " + std::to_string(k.id) + ")";
    k.model = std::string(t[1]);
    k.width_px = ParseInteger<int>(t[2], at, "WIDTH");
    k.height_px = ParseInteger<int>(t[3], at, "HEIGHT");
    if (k.width_px < 0 || k.height_px < 0) at.Fail("WIDTH HEIGHT", "must not be negative");
    for (std::size_t i = 4; i < t.size(); ++i) k.params.push_back(ParseReal(t[i], at, "PARAMS"));
    CheckModelParams(at, k);
    m->cameras.push_back(std::move(k));
  }
}

void ReadImagesText(Model* m) {
  std::ifstream in = OpenText(m->images_file);
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (IsBlankOrComment(line)) continue;
    Image image;
    EntryRef at{m->images_file, "line " + std::to_string(line_no)};
    const auto t = Tokens(line);
    NeedTokens(at, t, 10, "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    image.view.id = ParseInteger<std::uint32_t>(t[0], at, "IMAGE_ID");
    at.entry += " (IMAGE_ID " + std::to_string(image.view.id) + ")";
    double q[4], tr[3];
    for (int i = 0; i < 4; ++i) q[i] = ParseReal(t[1 + i], at, "QW QX QY QZ");
    for (int i = 0; i < 3; ++i) tr[i] = ParseReal(t[5 + i], at, "TX TY TZ");
    image.view.world_from_cam = PoseFromColmap(at, q, tr);
    image.view.intrinsics_id = ParseInteger<std::uint32_t>(t[8], at, "CAMERA_ID");
    // The name is the rest of the line (it may hold spaces).
    const std::size_t name_start = static_cast<std::size_t>(t[9].data() - line.data());
    std::string name = line.substr(name_start);
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
    image.view.name = std::move(name);
    image.entry = at.entry;

    // The POINTS2D line always follows (empty for an image without 2D points).
    std::string points_line;
    if (std::getline(in, points_line)) ++line_no;
    const EntryRef points_at{m->images_file, "line " + std::to_string(line_no) + " (POINTS2D of IMAGE_ID " +
                                                 std::to_string(image.view.id) + ")"};
    const auto p = Tokens(points_line);
    if (p.size() % 3 != 0) {
      points_at.Fail("", "expected (X Y POINT3D_ID) triples (got " + std::to_string(p.size()) + " values)");
    }
    for (std::size_t j = 0; j < p.size(); j += 3) {
      const std::string field = "POINTS2D[" + std::to_string(j / 3) + "]";
      const Eigen::Vector2d xy(ParseReal(p[j], points_at, field + ".X"),
                               ParseReal(p[j + 1], points_at, field + ".Y"));
      CheckFinite(points_at, field, xy.data(), 2);
      const auto id = ParseInteger<std::int64_t>(p[j + 2], points_at, field + ".POINT3D_ID");
      if (id < -1)
        points_at.Fail(field + ".POINT3D_ID", "must be -1 or an id (got " + std::to_string(id) + ")");
      image.xy.push_back(xy);
      image.point3d.push_back(id);
    }
    m->images.push_back(std::move(image));
  }
}

void ReadPointsText(Model* m) {
  std::ifstream in = OpenText(m->points_file);
  std::string line;
  for (std::size_t line_no = 1; std::getline(in, line); ++line_no) {
    if (IsBlankOrComment(line)) continue;
    Point point;
    point.where = line_no;
    EntryRef at{m->points_file, "line " + std::to_string(line_no)};
    const auto t = Tokens(line);
    NeedTokens(at, t, 8, "POINT3D_ID X Y Z R G B ERROR TRACK...");
    point.id = ParseInteger<std::int64_t>(t[0], at, "POINT3D_ID");
    if (point.id < 0) at.Fail("POINT3D_ID", "must not be negative");
    at = m->PointRef(point);
    for (int i = 0; i < 3; ++i) point.xyz[i] = ParseReal(t[1 + i], at, "X Y Z");
    CheckFinite(at, "X Y Z", point.xyz.data(), 3);
    for (int i = 0; i < 3; ++i) point.rgb[i] = ParseInteger<std::uint8_t>(t[4 + i], at, "R G B");
    ParseReal(t[7], at, "ERROR");
    if ((t.size() - 8) % 2 != 0) at.Fail("TRACK", "expected (IMAGE_ID POINT2D_IDX) pairs");
    for (std::size_t j = 8; j < t.size(); j += 2) {
      const std::string field = "TRACK[" + std::to_string((j - 8) / 2) + "]";
      point.track.emplace_back(ParseInteger<std::uint32_t>(t[j], at, field + ".IMAGE_ID"),
                               ParseInteger<std::uint32_t>(t[j + 1], at, field + ".POINT2D_IDX"));
    }
    m->points.push_back(std::move(point));
  }
}

// ---------------------------------------------------------------------------------------------- binary

// Bounds-checked little-endian reads over a whole file.
class BinaryReader {
 public:
  explicit BinaryReader(const std::filesystem::path& path) : at_{path, ""} {
    std::ifstream in(path, std::ios::binary);
    if (!in)
      throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "file not found");
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw FileError(path, "read error");
    bytes_ = std::move(s).str();
  }
  void SetEntry(std::string entry) { at_.entry = std::move(entry); }
  const EntryRef& at() const { return at_; }

  template <typename T>
  T Read(const char* field) {
    T v;
    Need(sizeof(T), field);
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string ReadCString(const char* field) {
    const auto end = bytes_.find('\0', pos_);
    if (end == std::string::npos) at_.Fail(field, "truncated (no terminating NUL)");
    std::string s = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return s;
  }
  // A count of records of at least `min_bytes` each: more than the rest of the file holds is an error
  // (a corrupt count must not trigger a huge allocation).
  std::uint64_t ReadCount(const char* field, std::size_t min_bytes) {
    const auto n = Read<std::uint64_t>(field);
    if (n > (bytes_.size() - pos_) / min_bytes) {
      at_.Fail(field, std::to_string(n) + " entries do not fit in the " +
                          std::to_string(bytes_.size() - pos_) + " bytes left: truncated or corrupt");
    }
    return n;
  }
  void ExpectEnd() const {
    if (pos_ != bytes_.size()) {
      throw FileError(at_.file, std::to_string(bytes_.size() - pos_) + " bytes after the last entry");
    }
  }

 private:
  void Need(std::size_t n, const char* field) const {
    if (bytes_.size() - pos_ < n) {
      at_.Fail(field, "truncated (file ends at byte " + std::to_string(bytes_.size()) + ")");
    }
  }
  EntryRef at_;
  std::string bytes_;
  std::size_t pos_ = 0;
};

void ReadCamerasBinary(Model* m) {
  BinaryReader in(m->cameras_file);
  const auto n = in.ReadCount("number of cameras", 24);
  for (std::uint64_t i = 0; i < n; ++i) {
    in.SetEntry("camera #" + std::to_string(i));
    SfmIntrinsics k;
    k.id = in.Read<std::uint32_t>("CAMERA_ID");
    in.SetEntry(in.at().entry + " (CAMERA_ID " + std::to_string(k.id) + ")");
    const auto model_id = in.Read<std::int32_t>("MODEL");
    const auto model = ColmapModelById(model_id);
    if (!model) in.at().Fail("MODEL", "unknown camera model id " + std::to_string(model_id));
    k.model = model->name;
    const auto width = in.Read<std::uint64_t>("WIDTH");
    const auto height = in.Read<std::uint64_t>("HEIGHT");
    if (width > INT32_MAX || height > INT32_MAX) in.at().Fail("WIDTH HEIGHT", "out of range");
    k.width_px = static_cast<int>(width);
    k.height_px = static_cast<int>(height);
    for (int j = 0; j < model->num_params; ++j) k.params.push_back(in.Read<double>("PARAMS"));
    CheckModelParams(in.at(), k);
    m->cameras.push_back(std::move(k));
  }
  in.ExpectEnd();
}

void ReadImagesBinary(Model* m) {
  BinaryReader in(m->images_file);
  const auto n = in.ReadCount("number of images", 73);
  for (std::uint64_t i = 0; i < n; ++i) {
    in.SetEntry("image #" + std::to_string(i));
    Image image;
    image.view.id = in.Read<std::uint32_t>("IMAGE_ID");
    in.SetEntry(in.at().entry + " (IMAGE_ID " + std::to_string(image.view.id) + ")");
    double q[4], t[3];
    for (double& x : q) x = in.Read<double>("QW QX QY QZ");
    for (double& x : t) x = in.Read<double>("TX TY TZ");
    image.view.world_from_cam = PoseFromColmap(in.at(), q, t);
    image.view.intrinsics_id = in.Read<std::uint32_t>("CAMERA_ID");
    image.view.name = in.ReadCString("NAME");
    const auto num_points = in.ReadCount("POINTS2D count", 24);
    image.xy.reserve(num_points);
    image.point3d.reserve(num_points);
    for (std::uint64_t j = 0; j < num_points; ++j) {
      Eigen::Vector2d xy;
      xy.x() = in.Read<double>("POINTS2D.X");
      xy.y() = in.Read<double>("POINTS2D.Y");
      const std::string field = "POINTS2D[" + std::to_string(j) + "]";
      CheckFinite(in.at(), field, xy.data(), 2);
      const auto id = in.Read<std::uint64_t>("POINTS2D.POINT3D_ID");
      if (id != kBinaryNoPoint3D && id > static_cast<std::uint64_t>(INT64_MAX)) {
        in.at().Fail(field + ".POINT3D_ID", "out of range");
      }
      image.xy.push_back(xy);
      image.point3d.push_back(id == kBinaryNoPoint3D ? -1 : static_cast<std::int64_t>(id));
    }
    image.entry = in.at().entry;
    m->images.push_back(std::move(image));
  }
  in.ExpectEnd();
}

void ReadPointsBinary(Model* m) {
  BinaryReader in(m->points_file);
  const auto n = in.ReadCount("number of points", 51);
  for (std::uint64_t i = 0; i < n; ++i) {
    Point point;
    point.where = i;
    in.SetEntry("point #" + std::to_string(i));
    const auto id = in.Read<std::uint64_t>("POINT3D_ID");
    if (id > static_cast<std::uint64_t>(INT64_MAX)) in.at().Fail("POINT3D_ID", "out of range");
    point.id = static_cast<std::int64_t>(id);
    in.SetEntry(m->PointRef(point).entry);
    for (int k = 0; k < 3; ++k) point.xyz[k] = in.Read<double>("X Y Z");
    CheckFinite(in.at(), "X Y Z", point.xyz.data(), 3);
    for (int k = 0; k < 3; ++k) point.rgb[k] = in.Read<std::uint8_t>("R G B");
    in.Read<double>("ERROR");
    const auto track_length = in.ReadCount("TRACK length", 8);
    point.track.reserve(track_length);
    for (std::uint64_t j = 0; j < track_length; ++j) {
      const auto image = in.Read<std::uint32_t>("TRACK.IMAGE_ID");
      point.track.emplace_back(image, in.Read<std::uint32_t>("TRACK.POINT2D_IDX"));
    }
    m->points.push_back(std::move(point));
  }
  in.ExpectEnd();
}

// ---------------------------------------------------------------------------------------------- assembly

void ReadLabels(const std::filesystem::path& path, const IdIndex& points, SfmReconstruction* r) {
  std::ifstream in = OpenText(path);
  std::vector<int> labels(r->num_points(), -1);
  std::string line;
  for (std::size_t line_no = 1; std::getline(in, line); ++line_no) {
    if (IsBlankOrComment(line)) continue;
    EntryRef at{path, "line " + std::to_string(line_no)};
    const auto t = Tokens(line);
    if (t.size() != 2) at.Fail("", "expected POINT3D_ID LABEL");
    const auto id = ParseInteger<std::int64_t>(t[0], at, "POINT3D_ID");
    const std::uint32_t point = points.Get(at, "POINT3D_ID", id);
    if (labels[point] >= 0) at.Fail("POINT3D_ID", "point " + std::to_string(id) + " labelled twice");
    labels[point] = ParseInteger<std::uint8_t>(t[1], at, "LABEL");
  }
  r->point_labels.resize(r->num_points());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0) throw FileError(path, "point " + std::to_string(r->point_ids[i]) + " has no label");
    r->point_labels[i] = static_cast<Label>(labels[i]);
  }
}

SfmReconstruction Assemble(Model&& m, const std::filesystem::path& dir) {
  SfmReconstruction r;
  IdIndex cameras("camera");
  for (std::size_t i = 0; i < m.cameras.size(); ++i) {
    cameras.Add({m.cameras_file, "CAMERA_ID " + std::to_string(m.cameras[i].id)}, "CAMERA_ID",
                m.cameras[i].id, static_cast<std::uint32_t>(i));
  }
  r.intrinsics = std::move(m.cameras);

  IdIndex points("3D point");
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    points.Add(m.PointRef(m.points[i]), "POINT3D_ID", m.points[i].id, static_cast<std::uint32_t>(i));
  }
  IdIndex images("image");
  for (std::size_t i = 0; i < m.images.size(); ++i) {
    const Image& image = m.images[i];
    const EntryRef at{m.images_file, image.entry};
    images.Add(at, "IMAGE_ID", image.view.id, static_cast<std::uint32_t>(i));
    cameras.Get(at, "CAMERA_ID", image.view.intrinsics_id);
    for (std::size_t j = 0; j < image.point3d.size(); ++j) {
      if (image.point3d[j] >= 0)
        points.Get(at, "POINTS2D[" + std::to_string(j) + "].POINT3D_ID", image.point3d[j]);
    }
    r.views.push_back(image.view);
  }

  r.point_ids.reserve(m.points.size());
  r.points_world.reserve(m.points.size());
  r.point_colors_rgb.reserve(m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Point& p = m.points[i];
    r.point_ids.push_back(p.id);
    r.points_world.push_back(p.xyz);
    r.point_colors_rgb.push_back(p.rgb);
    for (std::size_t j = 0; j < p.track.size(); ++j) {
      const auto [image_id, idx] = p.track[j];
      const std::string field = "TRACK[" + std::to_string(j) + "]";
      const std::uint32_t view = images.Get(m.PointRef(p), field + ".IMAGE_ID", image_id);
      const Image& image = m.images[view];
      if (idx >= image.xy.size()) {
        m.PointRef(p).Fail(field + ".POINT2D_IDX", std::to_string(idx) + " is beyond the " +
                                                       std::to_string(image.xy.size()) +
                                                       " 2D points of image " + std::to_string(image_id));
      }
      if (image.point3d[idx] != p.id) {
        const std::string owner = image.point3d[idx] < 0
                                      ? "has no 3D point"
                                      : "belongs to 3D point " + std::to_string(image.point3d[idx]);
        m.PointRef(p).Fail(field + ".POINT2D_IDX", "2D point " + std::to_string(idx) + " of image " +
                                                       std::to_string(image_id) + " " + owner + " in " +
                                                       m.images_file.filename().string());
      }
      r.observations.push_back({static_cast<std::uint32_t>(i), view, image.xy[idx]});
    }
  }
  m.points.clear();
  if (std::filesystem::exists(dir / kColmapLabelsFile)) ReadLabels(dir / kColmapLabelsFile, points, &r);
  r.SortObservations();
  r.AssertConsistent();
  return r;
}

}  // namespace

SfmReconstruction ReadColmapModel(const std::filesystem::path& dir, ColmapEncoding encoding) {
  if (!std::filesystem::is_directory(dir)) {
    throw FileError(dir, std::filesystem::exists(dir) ? "not a folder (a COLMAP model is a folder)"
                                                      : "COLMAP model folder not found");
  }
  Model m;
  m.encoding = encoding;
  const char* ext = Extension(encoding);
  m.cameras_file = dir / (std::string("cameras") + ext);
  m.images_file = dir / (std::string("images") + ext);
  m.points_file = dir / (std::string("points3D") + ext);
  if (encoding == ColmapEncoding::kText) {
    ReadCamerasText(&m);
    ReadImagesText(&m);
    ReadPointsText(&m);
  } else {
    ReadCamerasBinary(&m);
    ReadImagesBinary(&m);
    ReadPointsBinary(&m);
  }
  return Assemble(std::move(m), dir);
}

SfmReconstruction ReadColmapModel(const std::filesystem::path& dir) {
  bool binary = true;
  for (const char* f : {"cameras.bin", "images.bin", "points3D.bin"})
    binary &= std::filesystem::exists(dir / f);
  return ReadColmapModel(dir, binary ? ColmapEncoding::kBinary : ColmapEncoding::kText);
}

}  // namespace semap::io
