#include "io/kitti/calibration.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

namespace semap::io {
namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Rotation part of a 3x3 that should be a rotation: re-orthonormalised (KITTI prints 7 digits).
Eigen::Matrix3d Orthonormalise(const Eigen::Matrix3d& r) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d q = svd.matrixU() * svd.matrixV().transpose();
  if (q.determinant() < 0) q = -q;
  return q;
}

// Focal lengths accepted for an image whose larger side is 1 px (CheckIntrinsicsFitImage): from a very wide
// angle to a very long lens (KITTI: 0.58).
constexpr double kMinFocalPerSide = 0.05;
constexpr double kMaxFocalPerSide = 1000.0;

// Maximum deviation of R^T R from identity accepted for a calibration rotation (KITTI prints ~7 digits).
constexpr double kRotationTolerance = 1e-3;

Pose3d RigidFrom(const Eigen::Matrix3d& r, const Eigen::Vector3d& t, const std::filesystem::path& path,
                 const std::string& key) {
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRotationTolerance ||
      r.determinant() < 0) {
    throw FileError(path, "key '" + key + "' is not a rotation matrix");
  }
  Pose3d p = Pose3d::Identity();
  p.linear() = Orthonormalise(r);
  p.translation() = t;
  return p;
}

}  // namespace

KeyValueFile::KeyValueFile(const std::filesystem::path& path) : path_(path) {
  if (!std::filesystem::exists(path)) throw FileError(path, "calibration file not found");
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot open for reading");
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (Trim(line).empty()) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos || Trim(line.substr(0, colon)).empty()) {
      throw FileError(path, "line " + std::to_string(line_no) + " is not 'key: values'");
    }
    values_[Trim(line.substr(0, colon))] = line.substr(colon + 1);
  }
  if (in.bad()) throw FileError(path, "read error");
}

std::vector<double> KeyValueFile::Numbers(const std::string& key, size_t count) const {
  const auto it = values_.find(key);
  if (it == values_.end()) throw FileError(path_, "missing key '" + key + "'");
  std::istringstream is(it->second);
  std::vector<double> out;
  std::string token;
  while (is >> token) {
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      throw FileError(path_, "key '" + key + "': value '" + token + "' is not a number");
    }
    if (!std::isfinite(v)) {
      throw FileError(path_, "key '" + key + "': value " + std::to_string(out.size() + 1) + " is " + token +
                                 " (not finite)");
    }
    out.push_back(v);
  }
  if (out.size() != count) {
    throw FileError(path_, "key '" + key + "' has " + std::to_string(out.size()) + " values, expected " +
                               std::to_string(count));
  }
  return out;
}

Eigen::Matrix<double, 3, 4> KeyValueFile::Matrix34(const std::string& key) const {
  const auto v = Numbers(key, 12);
  Eigen::Matrix<double, 3, 4> m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = v[r * 4 + c];
  }
  return m;
}

Eigen::Matrix3d KeyValueFile::Matrix33(const std::string& key) const {
  const auto v = Numbers(key, 9);
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = v[r * 3 + c];
  }
  return m;
}

Eigen::Vector3d KeyValueFile::Vector3(const std::string& key) const {
  const auto v = Numbers(key, 3);
  return {v[0], v[1], v[2]};
}

StereoCalibration StereoFromProjections(const Eigen::Matrix<double, 3, 4>& p_left,
                                        const Eigen::Matrix<double, 3, 4>& p_right,
                                        const std::filesystem::path& path) {
  StereoCalibration s;
  s.fx_px = p_left(0, 0);
  s.fy_px = p_left(1, 1);
  s.cx_px = p_left(0, 2);
  s.cy_px = p_left(1, 2);
  if (!(s.fx_px > 0.0) || !(s.fy_px > 0.0)) throw FileError(path, "focal length is not positive");
  s.baseline_m = (p_left(0, 3) - p_right(0, 3)) / s.fx_px;
  if (!(s.baseline_m > 0.0)) {
    throw FileError(path, "stereo baseline " + std::to_string(s.baseline_m) +
                              " m is not positive (is the right camera to the right of the left one?)");
  }
  return s;
}

void CheckIntrinsicsFitImage(const StereoCalibration& s, const std::filesystem::path& path,
                             const std::string& key) {
  const double w = s.width_px, h = s.height_px;
  const std::string image = std::to_string(s.width_px) + "x" + std::to_string(s.height_px) + " image";
  auto number = [](double v) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, ec == std::errc() ? end : buf);
  };
  auto inside = [&](const char* name, double v, double size) {
    if (!(v >= 0.0 && v <= size)) {
      throw FileError(path, "key '" + key + "': principal point " + name + " = " + number(v) +
                                " px lies outside the " + image);
    }
  };
  inside("cx", s.cx_px, w);
  inside("cy", s.cy_px, h);
  const double side = std::max(w, h);
  for (const auto& [name, f] : {std::pair<const char*, double>{"fx", s.fx_px}, {"fy", s.fy_px}}) {
    if (!(f >= kMinFocalPerSide * side && f <= kMaxFocalPerSide * side)) {
      throw FileError(path, "key '" + key + "': focal length " + name + " = " + number(f) +
                                " px is implausible for a " + image + " (expected " +
                                number(kMinFocalPerSide * side) + " to " + number(kMaxFocalPerSide * side) +
                                ")");
    }
  }
}

Pose3d ReadRigidTransform(const std::filesystem::path& path) {
  const KeyValueFile f(path);
  return RigidFrom(f.Matrix33("R"), f.Vector3("T"), path, "R");
}

Pose3d TranslationX(double x_m) {
  Pose3d t = Pose3d::Identity();
  t.translation().x() = x_m;
  return t;
}

RawCalibration ReadRawCalibration(const std::filesystem::path& dir) {
  const KeyValueFile cam(dir / "calib_cam_to_cam.txt");
  const Eigen::Matrix<double, 3, 4> p2 = cam.Matrix34("P_rect_02");
  const Eigen::Matrix<double, 3, 4> p3 = cam.Matrix34("P_rect_03");
  RawCalibration out;
  out.stereo = StereoFromProjections(p2, p3, cam.path());
  const auto velo_path = dir / "calib_velo_to_cam.txt";
  if (std::filesystem::exists(velo_path)) {
    Pose3d rect00 = Pose3d::Identity();
    rect00.linear() =
        RigidFrom(cam.Matrix33("R_rect_00"), Eigen::Vector3d::Zero(), cam.path(), "R_rect_00").linear();
    const Pose3d cam0_from_velo = ReadRigidTransform(velo_path);
    out.cam2_from_velo = TranslationX(p2(0, 3) / out.stereo.fx_px) * rect00 * cam0_from_velo;
    const auto imu_path = dir / "calib_imu_to_velo.txt";
    if (std::filesystem::exists(imu_path)) {
      out.cam2_from_imu = *out.cam2_from_velo * ReadRigidTransform(imu_path);
    }
  }
  return out;
}

OdometryCalibration ReadOdometryCalibration(const std::filesystem::path& calib_txt, OdometryPair pair) {
  const KeyValueFile f(calib_txt);
  const bool color = pair == OdometryPair::kColor;
  const Eigen::Matrix<double, 3, 4> pl = f.Matrix34(color ? "P2" : "P0");
  const Eigen::Matrix<double, 3, 4> pr = f.Matrix34(color ? "P3" : "P1");
  OdometryCalibration out;
  out.stereo = StereoFromProjections(pl, pr, calib_txt);
  // P0 has no translation; P2's [0,3] is fx times cam 2's offset from cam 0 along x.
  if (color) out.cam_from_cam0 = TranslationX(pl(0, 3) / out.stereo.fx_px);
  if (f.Has("Tr")) {
    const Eigen::Matrix<double, 3, 4> tr = f.Matrix34("Tr");
    out.cam_from_velo = out.cam_from_cam0 * RigidFrom(tr.leftCols<3>(), tr.col(3), calib_txt, "Tr");
  }
  return out;
}

}  // namespace semap::io
