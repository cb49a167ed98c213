#include "io/output/trajectory_files.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "io/atomic_file.h"
#include "io/kitti/sequence_files.h"

namespace semap::io {
namespace {

// A quaternion this far from unit length is not a rotation (rounding in a written file stays far below).
constexpr double kUnitQuaternionTolerance = 1e-3;

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

}  // namespace

void WriteKittiPoses(const std::filesystem::path& path, const std::vector<Pose3d>& world_from_cam) {
  std::string text;
  for (const Pose3d& p : world_from_cam) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (r + c > 0) text += ' ';
        text += Format("%.9e", p.matrix()(r, c));
      }
    }
    text += '\n';
  }
  WriteFileAtomically(path, text);
}

std::vector<Pose3d> ReadKittiPoses(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot be read");
  size_t lines = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) ++lines;
  }
  return ReadOdometryPoses(path, lines);
}

void WriteTumTrajectory(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (const StampedPose& p : poses) {
    const Eigen::Quaterniond q(p.world_from_cam.linear());
    const Eigen::Vector3d t = p.world_from_cam.translation();
    text += Format("%.6f", p.timestamp_s);
    for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) text += ' ' + Format("%.9f", v);
    text += '\n';
  }
  WriteFileAtomically(path, text);
}

std::vector<StampedPose> ReadTumTrajectory(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot be read");
  std::vector<StampedPose> out;
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream is(line);
    double v[8];
    int n = 0;
    while (n < 8 && is >> v[n] && std::isfinite(v[n])) ++n;
    std::string rest;
    if (n != 8 || (is >> rest)) {
      throw FileError(
          path, "line " + std::to_string(line_no) + " is not 8 finite numbers (t tx ty tz qx qy qz qw)");
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > kUnitQuaternionTolerance) {
      throw FileError(path, "line " + std::to_string(line_no) + ": the quaternion is not of unit length");
    }
    StampedPose p;
    p.timestamp_s = v[0];
    p.world_from_cam.linear() = q.normalized().toRotationMatrix();
    p.world_from_cam.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    out.push_back(p);
  }
  return out;
}

}  // namespace semap::io
