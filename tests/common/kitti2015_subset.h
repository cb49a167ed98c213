// ../shared/data/kitti_stereo2015_subset for tests and benchmarks: frames through the io reader with their
// ground-truth disparity, and a small parser of the KITTI raw calibration files (P_rect_02 / P_rect_03,
// R_rect_00, velo-to-cam R, T) for generated sequences. Header-only so benchmarks can use it too.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/frame.h"
#include "io/frame_source.h"
#include "io/kitti/ground_truth.h"

namespace semap::test {

struct Stereo2015Frame {
  std::string name;         // e.g. "000002_10"
  Frame frame;              // left/right (BGR), calibration, velodyne (cam_from_velo into camera 2), id
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

// Frame `name` (e.g. "000002_10") read through the io reader (io::OpenFrameSource, stereo-2015 layout:
// images, calibration, Velodyne with cam_from_velo into camera 2) plus its disp_occ_0 ground truth.
inline Stereo2015Frame LoadStereo2015Frame(const std::filesystem::path& dir, const std::string& name) {
  io::FrameSourceOptions options;
  options.layout = io::DatasetLayout::kKittiStereo2015;
  options.first_frame = std::stoi(name.substr(0, name.find('_')));
  options.max_frames = 1;
  options.load_velodyne = true;
  auto source = io::OpenFrameSource(dir, options);
  std::optional<Frame> frame = source->Next();
  if (!frame || frame->id != options.first_frame)
    throw std::runtime_error("no frame " + name + " in " + dir.string());
  Stereo2015Frame f;
  f.name = name;
  f.frame = std::move(*frame);
  f.gt_disparity_px = io::ReadKittiDisparityPng(dir / "disp_occ_0" / (name + ".png"));
  return f;
}

}  // namespace semap::test
