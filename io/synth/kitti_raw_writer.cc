#include "io/synth/kitti_raw_writer.h"

#include <atomic>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>

#include "engine/core/parallel.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"
#include "io/synth/internal/synth_files.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;
using synth_internal::WriteText;

// Standard gravity, reported by the simulated IMU's up accelerometer.
constexpr double kGravityMps2 = 9.80665;
// Accuracy fields of the OXTS packets (metres, m/s), as a good RTK fix.
constexpr double kPosAccuracyM = 0.02;
constexpr double kVelAccuracyMps = 0.01;
constexpr char kCalibTime[] = "01-Jan-2026 12:00:00";

std::string Num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.12e", v);
  return buf;
}

std::string Nums(std::initializer_list<double> vs) {
  std::ostringstream os;
  bool first = true;
  for (double v : vs) {
    os << (first ? "" : " ") << Num(v);
    first = false;
  }
  return os.str();
}

std::string Matrix(const Eigen::Matrix3d& m) {
  return Nums({m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)});
}

std::string FrameName(int i, const char* ext) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%010d.%s", i, ext);
  return buf;
}

void WriteScan(const fs::path& path, const sim::LidarScan& scan) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw FileError(path, "cannot open for writing");
  static_assert(sizeof(Eigen::Vector4f) == 16);
  os.write(reinterpret_cast<const char*>(scan.points_velo.data()),
           static_cast<std::streamsize>(scan.points_velo.size() * sizeof(Eigen::Vector4f)));
  if (!os) throw FileError(path, "write failed");
}

const char kOxtsDataFormat[] =
    "lat:   latitude of the oxts-unit (deg)\nlon:   longitude of the oxts-unit (deg)\n"
    "alt:   altitude of the oxts-unit (m)\nroll:  roll angle (rad)\npitch: pitch angle (rad)\n"
    "yaw:   heading (rad), 0 = east, positive = counter clockwise\nvn:    velocity towards north (m/s)\n"
    "ve:    velocity towards east (m/s)\nvf:    forward velocity (m/s)\nvl:    leftward velocity (m/s)\n"
    "vu:    upward velocity (m/s)\nax:    acceleration in x (m/s^2)\nay:    acceleration in y (m/s^2)\n"
    "az:    acceleration in z (m/s^2)\naf:    forward acceleration (m/s^2)\nal:    leftward acceleration "
    "(m/s^2)\n"
    "au:    upward acceleration (m/s^2)\nwx:    angular rate around x (rad/s)\nwy:    angular rate around y "
    "(rad/s)\n"
    "wz:    angular rate around z (rad/s)\nwf:    angular rate around forward axis (rad/s)\n"
    "wl:    angular rate around leftward axis (rad/s)\nwu:    angular rate around upward axis (rad/s)\n"
    "pos_accuracy: position accuracy (north/east in m)\nvel_accuracy: velocity accuracy (north/east in m/s)\n"
    "navstat: navigation status\nnumsats: number of satellites tracked by primary GPS receiver\n"
    "posmode: position mode of primary GPS receiver\nvelmode: velocity mode of primary GPS receiver\n"
    "orimode: orientation mode of primary GPS receiver\n";

}  // namespace

SynthLayout SynthLayoutFor(const fs::path& root) {
  char drive[64];
  std::snprintf(drive, sizeof(drive), "%s_drive_%04d_sync", kSynthDate, kSynthDrive);
  return {root / kSynthDate, root / kSynthDate / drive};
}

std::string FormatKittiTimestamp(double t_s) {
  const auto ns_total = static_cast<std::int64_t>(std::llround(t_s * 1e9));
  const std::int64_t base_s = 12 * 3600;
  const std::int64_t secs = base_s + ns_total / 1000000000, ns = ns_total % 1000000000;
  const int day_offset = static_cast<int>(secs / 86400);
  const std::int64_t sod = secs % 86400;
  char buf[64];
  std::snprintf(buf, sizeof(buf), "2026-01-%02d %02d:%02d:%02d.%09" PRId64, 1 + day_offset,
                static_cast<int>(sod / 3600), static_cast<int>(sod / 60 % 60), static_cast<int>(sod % 60),
                ns);
  return buf;
}

std::string FormatCalibCamToCam(const sim::SensorRig& rig) {
  const StereoCalibration& c = rig.calibration;
  // x offsets of the rectified cameras from cam 0 (x_camN = x_cam0 + t): gray pair 0/1, colour pair 2/3.
  const double t[4] = {0.0, -c.baseline_m, rig.cam2_offset_x_m, rig.cam2_offset_x_m - c.baseline_m};
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  const double w = c.width_px, h = c.height_px;
  std::ostringstream os;
  os << "calib_time: " << kCalibTime << "\ncorner_dist: " << Num(0.0995) << "\n";
  for (int k = 0; k < 4; ++k) {
    char n[8];
    std::snprintf(n, sizeof(n), "%02d", k);
    os << "S_" << n << ": " << Nums({w, h}) << "\n";
    os << "K_" << n << ": " << Nums({c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1}) << "\n";
    os << "D_" << n << ": " << Nums({0, 0, 0, 0, 0}) << "\n";
    os << "R_" << n << ": " << Matrix(id) << "\n";
    os << "T_" << n << ": " << Nums({t[k], 0, 0}) << "\n";
    os << "S_rect_" << n << ": " << Nums({w, h}) << "\n";
    os << "R_rect_" << n << ": " << Matrix(id) << "\n";
    os << "P_rect_" << n << ": "
       << Nums({c.fx_px, 0, c.cx_px, c.fx_px * t[k], 0, c.fy_px, c.cy_px, 0, 0, 0, 1, 0}) << "\n";
  }
  return os.str();
}

std::string FormatCalibVeloToCam(const sim::SensorRig& rig) {
  const Eigen::Vector3d& t = rig.velo_to_cam_T;
  std::ostringstream os;
  os << "calib_time: " << kCalibTime << "\nR: " << Matrix(rig.velo_to_cam_R)
     << "\nT: " << Nums({t.x(), t.y(), t.z()}) << "\ndelta_f: " << Nums({0, 0})
     << "\ndelta_c: " << Nums({0, 0}) << "\n";
  return os.str();
}

std::string FormatCalibImuToVelo(const sim::SensorRig& rig) {
  const Eigen::Vector3d& t = rig.imu_to_velo_T;
  std::ostringstream os;
  os << "calib_time: " << kCalibTime << "\nR: " << Matrix(rig.imu_to_velo_R)
     << "\nT: " << Nums({t.x(), t.y(), t.z()}) << "\n";
  return os.str();
}

std::vector<OxtsPacket> SynthOxtsPackets(const sim::SyntheticSequence& seq) {
  const sim::SynthOptions& o = seq.options();
  // mercator_from_scene: rotate the scene by the heading, then put frame 0's IMU at the origin lat/lon/alt.
  OxtsPacket origin;
  origin.lat_deg = o.origin_latitude_deg;
  origin.lon_deg = o.origin_longitude_deg;
  origin.alt_m = o.origin_altitude_m;
  const OxtsPoseConverter devkit(origin);  // the reader's conversion, scale from the first latitude
  const double scale = devkit.mercator_scale();
  const Eigen::Vector3d origin_t = devkit.MercatorPose(origin).translation();
  Pose3d mercator_from_scene = Pose3d::Identity();
  mercator_from_scene.linear() =
      Eigen::AngleAxisd(o.origin_heading_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  mercator_from_scene.translation() =
      origin_t - mercator_from_scene.linear() * seq.scene_from_imu(0).translation();

  const int n = seq.num_frames();
  const double dt = 1.0 / o.frame_rate_hz;
  std::vector<OxtsPacket> packets(n);
  for (int i = 0; i < n; ++i) {
    OxtsPacket& p = packets[i];
    p = OxtsFromMercatorPose(mercator_from_scene * seq.scene_from_imu(i), scale);
    if (i == 0) {  // exactly the origin (the scale is taken from this latitude)
      p.lat_deg = origin.lat_deg;
      p.lon_deg = origin.lon_deg;
      p.alt_m = origin.alt_m;
    }
    // Velocities and rates by central differences of the true trajectory (informative only).
    const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
    if (b > a) {
      const Pose3d pa = mercator_from_scene * seq.scene_from_imu(a),
                   pb = mercator_from_scene * seq.scene_from_imu(b);
      const Eigen::Vector3d v_world = (pb.translation() - pa.translation()) / ((b - a) * dt);
      const Eigen::Vector3d v_body =
          (mercator_from_scene * seq.scene_from_imu(i)).linear().transpose() * v_world;
      p.ve = v_world.x(), p.vn = v_world.y(), p.vu = v_world.z();
      p.vf = v_body.x(), p.vl = v_body.y();
      const Eigen::AngleAxisd rot(pa.linear().transpose() * pb.linear());
      const Eigen::Vector3d w_body = rot.axis() * rot.angle() / ((b - a) * dt);
      p.wf = p.wx = w_body.x(), p.wl = p.wy = w_body.y(), p.wu = p.wz = w_body.z();
    }
    p.az = p.au = kGravityMps2;
    p.pos_accuracy = kPosAccuracyM;
    p.vel_accuracy = kVelAccuracyMps;
  }
  return packets;
}

SynthWriteSummary WriteSyntheticKittiRaw(const sim::SyntheticSequence& seq, const fs::path& root,
                                         const std::function<void(int, int)>& progress) {
  SynthWriteSummary summary;
  summary.layout = SynthLayoutFor(root);
  const fs::path& drive = summary.layout.drive_dir;
  const char* data_dirs[] = {"image_02", "image_03", "velodyne_points", "oxts", "semantic", "depth"};
  try {
    for (const char* d : data_dirs) fs::create_directories(drive / d / "data");
  } catch (const fs::filesystem_error& e) {
    throw FileError(drive, std::string("cannot create folders: ") + e.what());
  }
  WriteText(summary.layout.date_dir / "calib_cam_to_cam.txt", FormatCalibCamToCam(seq.rig()));
  WriteText(summary.layout.date_dir / "calib_velo_to_cam.txt", FormatCalibVeloToCam(seq.rig()));
  WriteText(summary.layout.date_dir / "calib_imu_to_velo.txt", FormatCalibImuToVelo(seq.rig()));

  const int n = seq.num_frames();
  std::string stamps, gt;
  for (int i = 0; i < n; ++i) {
    stamps += FormatKittiTimestamp(seq.trajectory().timestamp_s(i)) + "\n";
    const Eigen::Matrix4d m = seq.world_from_cam2(i).matrix();
    std::ostringstream os;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) os << Num(m(r, c)) << (r == 2 && c == 3 ? "\n" : " ");
    }
    gt += os.str();
  }
  for (const char* d : data_dirs) WriteText(drive / d / "timestamps.txt", stamps);
  WriteText(drive / "oxts" / "dataformat.txt", kOxtsDataFormat);
  WriteText(drive / "gt_world_from_cam2.txt", gt);
  const auto packets = SynthOxtsPackets(seq);
  for (int i = 0; i < n; ++i) {
    WriteOxtsFile(drive / "oxts" / "data" / FrameName(i, "txt"), packets[i]);
  }
  WriteMeshPly(drive / "scene_mesh.ply", seq.scene().ToMesh(seq.world_from_scene()),
               PlyEncoding::kBinaryLittleEndian, /*double_precision=*/true);

  std::vector<sim::LabelHistogram> histograms(n);
  std::vector<std::uint64_t> points(n, 0);
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  ParallelFor(0, n, 1, [&](int first, int last) {
    for (int i = first; i != last; ++i) {
      const sim::SyntheticFrame f = seq.RenderFrame(i);
      WritePng(drive / "image_02" / "data" / FrameName(i, "png"), f.left.color);
      WritePng(drive / "image_03" / "data" / FrameName(i, "png"), f.right.color);
      WritePng(drive / "semantic" / "data" / FrameName(i, "png"), f.left.labels);
      WriteDepthPngMm(drive / "depth" / "data" / FrameName(i, "png"), f.left.depth_m);
      WriteScan(drive / "velodyne_points" / "data" / FrameName(i, "bin"), f.scan);
      histograms[i].Add(f.left.labels);
      points[i] = f.scan.points_velo.size();
      const int k = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(k, n);
      }
    }
  });
  summary.num_frames = n;
  for (int i = 0; i < n; ++i) {
    summary.label_pixels.Merge(histograms[i]);
    summary.lidar_points += points[i];
  }
  return summary;
}

}  // namespace semap::io
