// Writing an SfmReconstruction as a COLMAP model (text and binary): io/sfm/colmap.h.
#include <Eigen/Geometry>
#include <array>
#include <bit>
#include <fstream>
#include <system_error>

#include "io/sfm/colmap.h"
#include "io/sfm/internal/camera_models.h"
#include "io/sfm/internal/sfm_checks.h"

namespace semap::io {

using namespace sfm_internal;

static_assert(std::endian::native == std::endian::little, "COLMAP .bin models are little-endian");

namespace {

void ColmapPose(const Pose3d& world_from_cam, double q[4], double t[3]) {
  const Pose3d cam_from_world = world_from_cam.inverse(Eigen::Isometry);
  const Eigen::Quaterniond quat(cam_from_world.linear());
  q[0] = quat.w();
  q[1] = quat.x();
  q[2] = quat.y();
  q[3] = quat.z();
  for (int i = 0; i < 3; ++i) t[i] = cam_from_world.translation()[i];
}

std::ofstream OpenForWriting(const std::filesystem::path& path, bool binary) {
  std::ofstream out(path, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
  if (!out) throw FileError(path, "cannot open for writing");
  if (!binary) out.precision(17);
  return out;
}

void Close(std::ofstream& out, const std::filesystem::path& path) {
  out.close();
  if (!out) throw FileError(path, "write failed");
}

template <typename T>
void Put(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Per view: its observations' indices, and per observation its POINT2D_IDX in its view.
struct ViewPoints {
  std::vector<std::vector<std::uint32_t>> observations;
  std::vector<std::uint32_t> point2d_idx;
};

ViewPoints GroupByView(const SfmReconstruction& r) {
  ViewPoints g;
  g.observations.resize(r.views.size());
  g.point2d_idx.resize(r.observations.size());
  for (std::uint32_t i = 0; i < r.observations.size(); ++i) {
    const SfmObservation& o = r.observations[i];
    if (!o.pixel_px.allFinite()) {
      throw std::invalid_argument("observation of point " + std::to_string(r.point_ids[o.point]) +
                                  " by view " + std::to_string(r.views[o.view].id) +
                                  " has no pixel position: COLMAP needs one");
    }
    auto& list = g.observations[o.view];
    g.point2d_idx[i] = static_cast<std::uint32_t>(list.size());
    list.push_back(i);
  }
  return g;
}

std::array<std::uint8_t, 3> Colour(const SfmReconstruction& r, std::size_t p) {
  return r.point_colors_rgb.empty() ? std::array<std::uint8_t, 3>{128, 128, 128} : r.point_colors_rgb[p];
}

void CheckIds(const SfmReconstruction& r) {
  for (const SfmView& v : r.views) {
    if (v.id < 0 || v.id > UINT32_MAX)
      throw std::invalid_argument("view id " + std::to_string(v.id) + ": COLMAP ids are uint32");
    if (r.FindIntrinsics(v.intrinsics_id) == nullptr) {
      throw std::invalid_argument("view " + std::to_string(v.id) +
                                  " has no intrinsics: COLMAP needs a camera");
    }
  }
  for (const SfmIntrinsics& k : r.intrinsics) {
    if (k.id < 0 || k.id > UINT32_MAX)
      throw std::invalid_argument("camera id " + std::to_string(k.id) + ": COLMAP ids are uint32");
  }
  for (std::int64_t id : r.point_ids) {
    if (id < 0)
      throw std::invalid_argument("point id " + std::to_string(id) + ": COLMAP ids are not negative");
  }
}

void WriteText(const std::filesystem::path& dir, const SfmReconstruction& r,
               const std::vector<SfmIntrinsics>& cams, const ViewPoints& g) {
  const auto cameras_path = dir / "cameras.txt";
  auto out = OpenForWriting(cameras_path, false);
  out << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      << "# Number of cameras: " << cams.size() << '\n';
  for (const SfmIntrinsics& k : cams) {
    out << k.id << ' ' << k.model << ' ' << k.width_px << ' ' << k.height_px;
    for (double p : k.params) out << ' ' << p;
    out << '\n';
  }
  Close(out, cameras_path);

  const auto images_path = dir / "images.txt";
  out = OpenForWriting(images_path, false);
  out << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      << "# Number of images: " << r.views.size() << '\n';
  for (std::size_t v = 0; v < r.views.size(); ++v) {
    const SfmView& view = r.views[v];
    double q[4], t[3];
    ColmapPose(view.world_from_cam, q, t);
    out << view.id;
    for (double x : q) out << ' ' << x;
    for (double x : t) out << ' ' << x;
    out << ' ' << view.intrinsics_id << ' ' << view.name << '\n';
    const char* sep = "";
    for (std::uint32_t i : g.observations[v]) {
      const SfmObservation& o = r.observations[i];
      out << sep << o.pixel_px.x() << ' ' << o.pixel_px.y() << ' ' << r.point_ids[o.point];
      sep = " ";
    }
    out << '\n';
  }
  Close(out, images_path);

  const auto points_path = dir / "points3D.txt";
  out = OpenForWriting(points_path, false);
  out << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      << "# Number of points: " << r.num_points() << '\n';
  std::size_t o = 0;
  for (std::uint32_t p = 0; p < r.num_points(); ++p) {
    const Eigen::Vector3d& X = r.points_world[p];
    const auto rgb = Colour(r, p);
    out << r.point_ids[p] << ' ' << X.x() << ' ' << X.y() << ' ' << X.z() << ' ' << int(rgb[0]) << ' '
        << int(rgb[1]) << ' ' << int(rgb[2]) << " -1";
    for (; o < r.observations.size() && r.observations[o].point == p; ++o) {
      out << ' ' << r.views[r.observations[o].view].id << ' ' << g.point2d_idx[o];
    }
    out << '\n';
  }
  Close(out, points_path);
}

void WriteBinary(const std::filesystem::path& dir, const SfmReconstruction& r,
                 const std::vector<SfmIntrinsics>& cams, const ViewPoints& g) {
  const auto cameras_path = dir / "cameras.bin";
  auto out = OpenForWriting(cameras_path, true);
  Put<std::uint64_t>(out, cams.size());
  for (const SfmIntrinsics& k : cams) {
    Put<std::uint32_t>(out, static_cast<std::uint32_t>(k.id));
    Put<std::int32_t>(out, ColmapModelByName(k.model)->id);
    Put<std::uint64_t>(out, static_cast<std::uint64_t>(k.width_px));
    Put<std::uint64_t>(out, static_cast<std::uint64_t>(k.height_px));
    for (double p : k.params) Put<double>(out, p);
  }
  Close(out, cameras_path);

  const auto images_path = dir / "images.bin";
  out = OpenForWriting(images_path, true);
  Put<std::uint64_t>(out, r.views.size());
  for (std::size_t v = 0; v < r.views.size(); ++v) {
    const SfmView& view = r.views[v];
    double q[4], t[3];
    ColmapPose(view.world_from_cam, q, t);
    Put<std::uint32_t>(out, static_cast<std::uint32_t>(view.id));
    for (double x : q) Put<double>(out, x);
    for (double x : t) Put<double>(out, x);
    Put<std::uint32_t>(out, static_cast<std::uint32_t>(view.intrinsics_id));
    out.write(view.name.c_str(), static_cast<std::streamsize>(view.name.size() + 1));
    Put<std::uint64_t>(out, g.observations[v].size());
    for (std::uint32_t i : g.observations[v]) {
      const SfmObservation& o = r.observations[i];
      Put<double>(out, o.pixel_px.x());
      Put<double>(out, o.pixel_px.y());
      Put<std::uint64_t>(out, static_cast<std::uint64_t>(r.point_ids[o.point]));
    }
  }
  Close(out, images_path);

  const auto points_path = dir / "points3D.bin";
  out = OpenForWriting(points_path, true);
  Put<std::uint64_t>(out, r.num_points());
  std::size_t o = 0;
  for (std::uint32_t p = 0; p < r.num_points(); ++p) {
    Put<std::uint64_t>(out, static_cast<std::uint64_t>(r.point_ids[p]));
    for (int k = 0; k < 3; ++k) Put<double>(out, r.points_world[p][k]);
    for (std::uint8_t c : Colour(r, p)) Put<std::uint8_t>(out, c);
    Put<double>(out, -1.0);
    std::size_t end = o;
    while (end < r.observations.size() && r.observations[end].point == p) ++end;
    Put<std::uint64_t>(out, end - o);
    for (; o < end; ++o) {
      Put<std::uint32_t>(out, static_cast<std::uint32_t>(r.views[r.observations[o].view].id));
      Put<std::uint32_t>(out, g.point2d_idx[o]);
    }
  }
  Close(out, points_path);
}

}  // namespace

void WriteColmapModel(const std::filesystem::path& dir, const SfmReconstruction& r, ColmapEncoding encoding) {
  r.AssertConsistent();
  CheckIds(r);
  std::vector<SfmIntrinsics> cams;
  for (const SfmIntrinsics& k : r.intrinsics) cams.push_back(AsColmapModel(k));
  const ViewPoints g = GroupByView(r);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (encoding == ColmapEncoding::kText) {
    WriteText(dir, r, cams, g);
  } else {
    WriteBinary(dir, r, cams, g);
  }
  const auto labels_path = dir / kColmapLabelsFile;
  if (!r.point_labels.empty()) {
    auto out = OpenForWriting(labels_path, false);
    out << "# semap: POINT3D_ID LABEL, one line per 3D point\n";
    for (std::size_t p = 0; p < r.num_points(); ++p)
      out << r.point_ids[p] << ' ' << int(r.point_labels[p]) << '\n';
    Close(out, labels_path);
  } else {
    std::filesystem::remove(labels_path, ec);  // a stale file would label the new points
  }
}

}  // namespace semap::io
