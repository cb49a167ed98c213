#include "io/kitti/oxts.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace semap::io {

OxtsPacket ParseOxtsLine(const std::string& line, const std::filesystem::path& path) {
  OxtsPacket p;
  std::istringstream is(line);
  std::string token;
  size_t n = 0;
  while (is >> token) {
    if (n == p.values.size()) throw FileError(path, "OXTS line has more than 30 values");
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      throw FileError(path, "OXTS value " + std::to_string(n + 1) + " '" + token + "' is not a number");
    }
    if (!std::isfinite(v)) throw FileError(path, "OXTS value " + std::to_string(n + 1) + " is not finite");
    p.values[n++] = v;
  }
  if (n != p.values.size()) {
    throw FileError(path, "OXTS line has " + std::to_string(n) + " values, expected 30");
  }
  if (!(std::abs(p.lat_deg()) < 90.0)) throw FileError(path, "OXTS latitude is outside (-90, 90) degrees");
  return p;
}

OxtsPacket ReadOxtsFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw FileError(path, std::filesystem::exists(path) ? "cannot open for reading" : "OXTS file not found");
  std::string line;
  if (!std::getline(in, line)) throw FileError(path, "empty OXTS file");
  return ParseOxtsLine(line, path);
}

void WriteOxtsFile(const std::filesystem::path& path, const OxtsPacket& packet) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw FileError(path, "cannot open for writing");
  for (size_t i = 0; i < packet.values.size(); ++i) {
    char buf[64];
    const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), packet.values[i]);
    out << (i ? " " : "") << std::string_view(buf, static_cast<size_t>(ptr - buf));
  }
  out << "\n";
  out.close();
  if (!out) throw FileError(path, "write failed");
}

OxtsPoseConverter::OxtsPoseConverter(const OxtsPacket& first)
    : scale_(std::cos(first.lat_deg() * std::numbers::pi / 180.0)) {
  first_from_mercator_ = MercatorPose(first).inverse();
}

Pose3d OxtsPoseConverter::MercatorPose(const OxtsPacket& p) const {
  constexpr double pi = std::numbers::pi;
  const double er = kOxtsEarthRadiusM;
  const double tx = scale_ * p.lon_deg() * pi * er / 180.0;
  const double ty = scale_ * er * std::log(std::tan((90.0 + p.lat_deg()) * pi / 360.0));
  Pose3d pose = Pose3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(p.yaw_rad(), Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(p.pitch_rad(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(p.roll_rad(), Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(tx, ty, p.alt_m());
  return pose;
}

Pose3d OxtsPoseConverter::WorldFromImu(const OxtsPacket& packet) const {
  return first_from_mercator_ * MercatorPose(packet);
}

}  // namespace semap::io
