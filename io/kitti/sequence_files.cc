#include "io/kitti/sequence_files.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace semap::io {
namespace {

// Maximum deviation of a pose's rotation from orthonormal (KITTI prints ~7-9 digits).
constexpr double kRotationTolerance = 1e-3;

std::vector<std::string> ReadLines(const std::filesystem::path& path, const char* what) {
  std::ifstream in(path);
  if (!in)
    throw FileError(
        path, std::filesystem::exists(path) ? "cannot open for reading" : std::string(what) + " not found");
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  // Trailing empty lines are not entries.
  while (!lines.empty() && lines.back().find_first_not_of(" \t") == std::string::npos) lines.pop_back();
  if (in.bad()) throw FileError(path, "read error");
  return lines;
}

}  // namespace

double ParseKittiTimestamp(const std::string& text, const std::filesystem::path& path, int line_no) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, consumed = 0;
  double s = 0.0;
  const int n = std::sscanf(text.c_str(), "%d-%d-%d %d:%d:%lf%n", &y, &mo, &d, &h, &mi, &s, &consumed);
  const bool rest_blank =
      n == 6 && text.find_first_not_of(" \t", static_cast<size_t>(consumed)) == std::string::npos;
  const std::chrono::year_month_day ymd{std::chrono::year{y}, std::chrono::month{static_cast<unsigned>(mo)},
                                        std::chrono::day{static_cast<unsigned>(d)}};
  if (!rest_blank || !ymd.ok() || h < 0 || h > 23 || mi < 0 || mi > 59 || !(s >= 0.0 && s < 61.0)) {
    throw FileError(path, "line " + std::to_string(line_no) + ": '" + text +
                              "' is not a timestamp 'YYYY-MM-DD HH:MM:SS.fffffffff'");
  }
  const auto days = std::chrono::sys_days(ymd).time_since_epoch().count();
  return static_cast<double>(days) * 86400.0 + h * 3600.0 + mi * 60.0 + s;
}

std::vector<double> ReadKittiTimestamps(const std::filesystem::path& path) {
  const auto lines = ReadLines(path, "timestamps file");
  std::vector<double> out;
  out.reserve(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    out.push_back(ParseKittiTimestamp(lines[i], path, static_cast<int>(i + 1)));
  }
  for (size_t i = 1; i < out.size(); ++i) out[i] -= out[0];
  if (!out.empty()) out[0] = 0.0;
  return out;
}

std::vector<double> ReadOdometryTimes(const std::filesystem::path& path) {
  const auto lines = ReadLines(path, "times file");
  std::vector<double> out;
  out.reserve(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    std::istringstream is(lines[i]);
    double t = 0.0;
    std::string rest;
    if (!(is >> t) || (is >> rest) || !std::isfinite(t)) {
      throw FileError(path,
                      "line " + std::to_string(i + 1) + ": '" + lines[i] + "' is not a time in seconds");
    }
    out.push_back(t);
  }
  for (size_t i = 1; i < out.size(); ++i) out[i] -= out[0];
  if (!out.empty()) out[0] = 0.0;
  return out;
}

std::vector<Pose3d> ReadOdometryPoses(const std::filesystem::path& path, size_t count) {
  const auto lines = ReadLines(path, "poses file");
  if (lines.size() < count) {
    throw FileError(path, "has " + std::to_string(lines.size()) + " poses but " + std::to_string(count) +
                              " frames need one each");
  }
  std::vector<Pose3d> poses;
  poses.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    std::istringstream is(lines[i]);
    Eigen::Matrix<double, 3, 4> m;
    std::string token;
    int n = 0;
    while (is >> token) {
      double v = 0.0;
      const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
      if (n >= 12 || ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(v)) {
        n = -1;
        break;
      }
      m(n / 4, n % 4) = v;
      ++n;
    }
    if (n != 12) {
      throw FileError(path,
                      "line " + std::to_string(i + 1) + " is not 12 finite numbers (3×4 row-major pose)");
    }
    const Eigen::Matrix3d r = m.leftCols<3>();
    if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRotationTolerance) {
      throw FileError(path, "line " + std::to_string(i + 1) + ": the 3×3 part is not a rotation");
    }
    Pose3d p = Pose3d::Identity();
    p.linear() = r;
    p.translation() = m.col(3);
    poses.push_back(p);
  }
  return poses;
}

}  // namespace semap::io
