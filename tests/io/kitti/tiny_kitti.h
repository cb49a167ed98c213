// Small KITTI-style datasets written by the tests themselves (tiny images, a few frames), with every value
// known so the readers' output can be checked exactly.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "engine/core/calibration.h"

namespace semap::test {

struct TinyRawOptions {
  int num_frames = 4;
  int width_px = 32;
  int height_px = 16;
  bool velodyne = true;
  bool oxts = true;
  bool labels = true;
  bool timestamps = true;
};

// The numbers the tiny raw sequence is written with.
struct TinyRawTruth {
  double fx_px = 100.0, fy_px = 101.0, cx_px = 15.5, cy_px = 7.5;
  double cam2_offset_m = 0.06;  // P_rect_02[0,3] / fx
  double baseline_m = 0.54;
  double rect_angle_rad = 0.01;  // R_rect_00 = Ry(angle)
  double lat0_deg = 49.011, lon0_deg = 8.4237, alt0_m = 112.5;
  double step_north_m = 1.0;  // the vehicle moves north by this each frame, heading north
  double frame_period_s = 0.1037;
  Pose3d cam0_from_velo;  // [R|T] of calib_velo_to_cam.txt
  Pose3d velo_from_imu;   // [R|T] of calib_imu_to_velo.txt
  TinyRawTruth();
};

struct TinyRaw {
  std::filesystem::path root;   // ROOT
  std::filesystem::path date;   // ROOT/2011_09_26 (calibration files)
  std::filesystem::path drive;  // ROOT/2011_09_26/2011_09_26_drive_0001_sync
  TinyRawTruth truth;
};

// Writes ROOT/2011_09_26/2011_09_26_drive_0001_sync with images, Velodyne scans, OXTS, timestamps and
// semantic labels as selected.
TinyRaw WriteTinyRaw(const std::filesystem::path& root, const TinyRawOptions& options = {});

// The left / right image written for frame i (deterministic content), and its label image.
cv::Mat TinyImage(int frame, int width_px, int height_px, bool right);
cv::Mat TinyLabels(int frame, int width_px, int height_px);
// Velodyne points of frame i.
std::vector<Eigen::Vector4f> TinyScan(int frame);

// Replaces a file by its first `keep_bytes` bytes.
void TruncateFile(const std::filesystem::path& path, size_t keep_bytes);
void WriteTextFile(const std::filesystem::path& path, const std::string& text);
std::string ReadTextFile(const std::filesystem::path& path);

}  // namespace semap::test
