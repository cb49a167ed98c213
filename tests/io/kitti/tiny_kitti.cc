#include "tests/io/kitti/tiny_kitti.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "io/kitti/oxts.h"
#include "io/kitti/velodyne.h"

namespace semap::test {
namespace {

namespace fs = std::filesystem;

std::string Frame10(int i) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%010d", i);
  return buf;
}

std::string Row(const Eigen::MatrixXd& m) {
  std::ostringstream os;
  os.precision(12);
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = 0; c < m.cols(); ++c) os << ' ' << m(r, c);
  }
  return os.str();
}

std::string RigidText(const Pose3d& p) {
  return "calib_time: 15-Mar-2012 11:37:16\nR:" + Row(p.linear()) +
         "\nT:" + Row(p.translation().transpose()) + "\ndelta_f: 0 0\ndelta_c: 0 0\n";
}

void WriteStamps(const fs::path& dir, int n, double period_s) {
  std::ofstream out(dir / "timestamps.txt");
  for (int i = 0; i < n; ++i) {
    const double s = 25.964389445 + i * period_s;
    char buf[64];
    std::snprintf(buf, sizeof(buf), "2011-09-26 13:02:%012.9f\n", s);
    out << buf;
  }
}

}  // namespace

TinyRawTruth::TinyRawTruth() {
  cam0_from_velo = Pose3d::Identity();
  cam0_from_velo.linear() << 0, -1, 0, 0, 0, -1, 1, 0, 0;  // velodyne x forward → camera z forward
  cam0_from_velo.translation() = Eigen::Vector3d(0.1, -0.08, -0.27);
  velo_from_imu = Pose3d::Identity();
  velo_from_imu.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  velo_from_imu.translation() = Eigen::Vector3d(-0.81, 0.32, -0.80);
}

cv::Mat TinyImage(int frame, int width_px, int height_px, bool right) {
  cv::Mat m(height_px, width_px, CV_8UC3);
  for (int r = 0; r < height_px; ++r) {
    for (int c = 0; c < width_px; ++c) {
      m.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<uchar>(frame * 10 + (right ? 5 : 0)),
                                        static_cast<uchar>(r * 7), static_cast<uchar>(c * 3));
    }
  }
  return m;
}

cv::Mat TinyLabels(int frame, int width_px, int height_px) {
  cv::Mat m(height_px, width_px, CV_8UC1);
  for (int r = 0; r < height_px; ++r) {
    for (int c = 0; c < width_px; ++c) {
      // Bottom half road (1), top half building (3), one column of car (14) shifted by frame.
      m.at<uchar>(r, c) = c == frame ? 14 : (r >= height_px / 2 ? 1 : 3);
    }
  }
  return m;
}

std::vector<Eigen::Vector4f> TinyScan(int frame) {
  std::vector<Eigen::Vector4f> pts;
  for (int k = 0; k < 5 + frame; ++k) pts.emplace_back(5.0f + k, 0.5f * k - 1.0f, -1.5f, 0.01f * frame);
  return pts;
}

TinyRaw WriteTinyRaw(const fs::path& root, const TinyRawOptions& o) {
  TinyRaw t;
  const TinyRawTruth& g = t.truth;
  t.root = root;
  t.date = root / "2011_09_26";
  t.drive = t.date / "2011_09_26_drive_0001_sync";
  for (const char* sub : {"image_02/data", "image_03/data"}) fs::create_directories(t.drive / sub);

  // Calibration in the date folder.
  Eigen::Matrix<double, 3, 4> p2, p3;
  p2 << g.fx_px, 0, g.cx_px, g.fx_px * g.cam2_offset_m, 0, g.fy_px, g.cy_px, 0, 0, 0, 1, 0;
  p3 = p2;
  p3(0, 3) = g.fx_px * (g.cam2_offset_m - g.baseline_m);
  const Eigen::Matrix3d rect =
      Eigen::AngleAxisd(g.rect_angle_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  std::ostringstream cam;
  cam << "calib_time: 09-Jan-2012 13:57:47\ncorner_dist: 9.950000e-02\n";
  cam << "S_rect_02: " << o.width_px << " " << o.height_px << "\nR_rect_00:" << Row(rect)
      << "\nP_rect_02:" << Row(p2) << "\nP_rect_03:" << Row(p3) << "\n";
  WriteTextFile(t.date / "calib_cam_to_cam.txt", cam.str());
  WriteTextFile(t.date / "calib_velo_to_cam.txt", RigidText(g.cam0_from_velo));
  WriteTextFile(t.date / "calib_imu_to_velo.txt", RigidText(g.velo_from_imu));

  for (int i = 0; i < o.num_frames; ++i) {
    const std::string png = Frame10(i) + ".png";
    cv::imwrite((t.drive / "image_02/data" / png).string(), TinyImage(i, o.width_px, o.height_px, false));
    cv::imwrite((t.drive / "image_03/data" / png).string(), TinyImage(i, o.width_px, o.height_px, true));
  }
  if (o.timestamps) {
    WriteStamps(t.drive / "image_02", o.num_frames, g.frame_period_s);
    WriteStamps(t.drive / "image_03", o.num_frames, g.frame_period_s);
  }
  if (o.velodyne) {
    fs::create_directories(t.drive / "velodyne_points/data");
    for (int i = 0; i < o.num_frames; ++i) {
      io::WriteVelodyneBin(t.drive / "velodyne_points/data" / (Frame10(i) + ".bin"), TinyScan(i));
    }
  }
  if (o.oxts) {
    fs::create_directories(t.drive / "oxts/data");
    // Heading north (yaw = π/2), one step north per frame: Δlat = step / er in radians.
    for (int i = 0; i < o.num_frames; ++i) {
      io::OxtsPacket p;
      p.values[0] = g.lat0_deg + i * g.step_north_m / io::kOxtsEarthRadiusM * 180.0 / std::numbers::pi;
      p.values[1] = g.lon0_deg;
      p.values[2] = g.alt0_m;
      p.values[5] = std::numbers::pi / 2;
      p.values[24] = 4;  // navstat
      io::WriteOxtsFile(t.drive / "oxts/data" / (Frame10(i) + ".txt"), p);
    }
  }
  if (o.labels) {
    fs::create_directories(t.drive / "semantic/data");
    for (int i = 0; i < o.num_frames; ++i) {
      cv::imwrite((t.drive / "semantic/data" / (Frame10(i) + ".png")).string(),
                  TinyLabels(i, o.width_px, o.height_px));
    }
  }
  return t;
}

void TruncateFile(const fs::path& path, size_t keep_bytes) {
  const std::string text = ReadTextFile(path);
  WriteTextFile(path, text.substr(0, keep_bytes));
}

void WriteTextFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string ReadTextFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace semap::test
