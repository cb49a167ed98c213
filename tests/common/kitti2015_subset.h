// Reads ../shared/data/kitti_stereo2015_subset without the io readers (test and benchmark helper): the
// left/right images, the ground-truth disparity, the Velodyne scan and the raw-data calibration
// (P_rect_02 / P_rect_03, R_rect_00, velo-to-cam R, T). Header-only so benchmarks can use it too.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "engine/core/frame.h"

namespace semap::test {

struct Stereo2015Frame {
  std::string name;     // e.g. "000002_10"
  Frame frame;          // left/right (BGR), calibration, velodyne (cam_from_velo into camera 2), id
  cv::Mat gt_disparity_px;  // CV_32F, 0 = no ground truth (disp_occ_0)
};

inline std::map<std::string, std::vector<double>> ReadKittiCalibFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  std::map<std::string, std::vector<double>> out;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream values(line.substr(colon + 1));
    std::vector<double> v;
    double x;
    while (values >> x) v.push_back(x);
    out[line.substr(0, colon)] = v;
  }
  return out;
}

// Calibration of image_2 (left) / image_3 (right) and cam2_from_velo.
inline void ReadStereo2015Calibration(const std::filesystem::path& dir, StereoCalibration* calib,
                                      Pose3d* cam_from_velo) {
  auto cam = ReadKittiCalibFile(dir / "calib_cam_to_cam.txt");
  auto velo = ReadKittiCalibFile(dir / "calib_velo_to_cam.txt");
  const auto& p2 = cam.at("P_rect_02");
  const auto& p3 = cam.at("P_rect_03");
  const auto& r_rect = cam.at("R_rect_00");
  const auto& s = cam.at("S_rect_02");
  if (p2.size() != 12 || p3.size() != 12 || r_rect.size() != 9 || s.size() != 2) {
    throw std::runtime_error("malformed calib_cam_to_cam.txt in " + dir.string());
  }
  calib->fx_px = p2[0];
  calib->fy_px = p2[5];
  calib->cx_px = p2[2];
  calib->cy_px = p2[6];
  calib->baseline_m = (p2[3] - p3[3]) / p2[0];
  calib->width_px = static_cast<int>(s[0]);
  calib->height_px = static_cast<int>(s[1]);
  // P_rect_02 = K [I | t]: t_z = P[2,3], t_x = (P[0,3] − cx t_z) / fx, t_y = (P[1,3] − cy t_z) / fy.
  const double tz = p2[11];
  const Eigen::Vector3d t((p2[3] - p2[2] * tz) / p2[0], (p2[7] - p2[6] * tz) / p2[5], tz);
  Eigen::Matrix3d rr, rv;
  for (int i = 0; i < 9; ++i) rr(i / 3, i % 3) = r_rect[i];
  const auto& r = velo.at("R");
  const auto& tv = velo.at("T");
  for (int i = 0; i < 9; ++i) rv(i / 3, i % 3) = r[i];
  Pose3d rect0_from_velo = Pose3d::Identity();
  rect0_from_velo.linear() = rr * rv;
  rect0_from_velo.translation() = rr * Eigen::Vector3d(tv[0], tv[1], tv[2]);
  Pose3d cam2_from_rect0 = Pose3d::Identity();
  cam2_from_rect0.translation() = t;
  *cam_from_velo = cam2_from_rect0 * rect0_from_velo;
}

inline std::vector<std::string> ListStereo2015Frames(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir / "image_2")) {
    if (e.path().extension() == ".png") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

inline Stereo2015Frame LoadStereo2015Frame(const std::filesystem::path& dir, const std::string& name) {
  Stereo2015Frame f;
  f.name = name;
  f.frame.id = std::stoll(name.substr(0, name.find('_')));
  f.frame.left = cv::imread((dir / "image_2" / (name + ".png")).string(), cv::IMREAD_COLOR);
  f.frame.right = cv::imread((dir / "image_3" / (name + ".png")).string(), cv::IMREAD_COLOR);
  if (f.frame.left.empty() || f.frame.right.empty()) throw std::runtime_error("cannot read images " + name);
  VelodyneScan scan;
  ReadStereo2015Calibration(dir, &f.frame.calibration, &scan.cam_from_velo);
  f.frame.calibration.width_px = f.frame.left.cols;
  f.frame.calibration.height_px = f.frame.left.rows;
  const cv::Mat gt = cv::imread((dir / "disp_occ_0" / (name + ".png")).string(), cv::IMREAD_UNCHANGED);
  if (gt.type() != CV_16UC1) throw std::runtime_error("bad ground truth disparity " + name);
  gt.convertTo(f.gt_disparity_px, CV_32F, 1.0 / 256.0);
  {
    std::ifstream in(dir / "velodyne" / (name + ".bin"), std::ios::binary | std::ios::ate);
    if (in) {
      const auto bytes = static_cast<std::size_t>(in.tellg());
      in.seekg(0);
      scan.points_velo.resize(bytes / sizeof(Eigen::Vector4f));
      in.read(reinterpret_cast<char*>(scan.points_velo.data()),
              static_cast<std::streamsize>(scan.points_velo.size() * sizeof(Eigen::Vector4f)));
      f.frame.velodyne = std::move(scan);
    }
  }
  return f;
}

}  // namespace semap::test
