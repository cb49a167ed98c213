#include "engine/sim/lidar_scanner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/sim/synthetic_sequence.h"

namespace semap::sim {
namespace {

SynthOptions Opts(double noise_m) {
  SynthOptions o;
  o.preset = ScenePreset::kUrban;
  o.num_frames = 10;
  o.seed = 21;
  o.lidar_range_noise_m = noise_m;
  return o;
}

double Quantile(std::vector<double> v, double q) {
  const size_t k = static_cast<size_t>(q * (v.size() - 1));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// Noise-free Velodyne points projected into the left image agree with the depth map. The depth at the
// sub-pixel projection is interpolated bilinearly in inverse depth (exact on a plane) from the four
// neighbouring pixels, where they lie on one plane with the point's label, for the points the camera sees
// (the scanner sits 0.27 m behind the camera and sees some surfaces the camera does not).
TEST(LidarScanner, PointsAgreeWithDepthMapsSubCentimetre) {
  const SyntheticSequence seq(Opts(0.0));
  const StereoCalibration& cal = seq.rig().calibration;
  const CameraRenderer renderer(seq.scene(), seq.options());
  const LidarScanner scanner(seq.scene(), seq.bvh(), seq.options());
  for (int frame : {0, 9}) {
    const LidarScan scan = scanner.Scan(seq.scene_from_velo(frame), 1);
    const CameraImage img = renderer.RenderGeometry(cal, seq.scene_from_cam2(frame));
    const Pose3d cam_from_velo = seq.rig().cam2_from_velo();
    const Pose3d scene_from_cam = seq.scene_from_cam2(frame);
    int occluded = 0;
    std::vector<double> err;
    int in_image = 0;
    for (size_t k = 0; k < scan.points_velo.size(); ++k) {
      const Eigen::Vector3d p = cam_from_velo * scan.points_velo[k].head<3>().cast<double>();
      if (p.z() < 1.0) continue;
      const Eigen::Vector2d uv = cal.Project(p);
      const int x0 = static_cast<int>(std::floor(uv.x())), y0 = static_cast<int>(std::floor(uv.y()));
      if (x0 < 1 || y0 < 1 || x0 + 2 >= cal.width_px || y0 + 2 >= cal.height_px) continue;
      ++in_image;
      const Eigen::Vector3d to_point = scene_from_cam.linear() * p;
      if (seq.bvh().Intersect(scene_from_cam.translation(), to_point, 0.0, 1.0 - 1e-4)) {
        ++occluded;
        continue;
      }
      // The 4x4 pixels around the point: same label, and inverse depth affine (zero second differences
      // along rows and columns), i.e. one plane.
      double inv4[4][4];
      bool ok = true;
      for (int r = 0; r < 4 && ok; ++r) {
        for (int c = 0; c < 4 && ok; ++c) {
          const float z = img.depth_m.at<float>(y0 - 1 + r, x0 - 1 + c);
          ok = z > 0.0f && img.labels.at<std::uint8_t>(y0 - 1 + r, x0 - 1 + c) == scan.labels[k];
          inv4[r][c] = 1.0 / z;
        }
      }
      for (int r = 0; r < 4 && ok; ++r) {
        for (int c = 0; c < 2 && ok; ++c) {
          ok = std::abs(inv4[r][c] - 2 * inv4[r][c + 1] + inv4[r][c + 2]) < 1e-5 * inv4[1][1] &&
               std::abs(inv4[c][r] - 2 * inv4[c + 1][r] + inv4[c + 2][r]) < 1e-5 * inv4[1][1];
        }
      }
      if (!ok) continue;
      const double inv[4] = {inv4[1][1], inv4[1][2], inv4[2][1], inv4[2][2]};
      const double fx = uv.x() - x0, fy = uv.y() - y0;
      const double inv_z =
          (1 - fy) * ((1 - fx) * inv[0] + fx * inv[1]) + fy * ((1 - fx) * inv[2] + fx * inv[3]);
      err.push_back(std::abs(1.0 / inv_z - p.z()));
    }
    ASSERT_GT(in_image, 15000) << "frame " << frame;
    EXPECT_LT(occluded, 0.1 * in_image) << "frame " << frame;
    ASSERT_GT(err.size(), 0.6 * (in_image - occluded)) << "frame " << frame;
    // The rare larger errors are sub-pixel gaps (fence boards seen at a grazing angle) that a depth map
    // sampled at pixel centres cannot show.
    RecordProperty("median_error_m_frame" + std::to_string(frame), std::to_string(Quantile(err, 0.5)));
    EXPECT_LT(Quantile(err, 0.5), 1e-3) << "frame " << frame;
    EXPECT_LT(Quantile(err, 0.95), 5e-3) << "frame " << frame;
    EXPECT_LT(Quantile(err, 0.99), 1e-2) << "frame " << frame;
  }
}

TEST(LidarScanner, Hdl64LikeScanWithRangeNoise) {
  const SynthOptions o = Opts(0.02);
  const SyntheticSequence noisy(o);
  const SyntheticSequence exact(Opts(0.0));
  const LidarScanner scanner_noisy(noisy.scene(), noisy.bvh(), noisy.options());
  const LidarScanner scanner_exact(exact.scene(), exact.bvh(), exact.options());
  const LidarScan a = scanner_noisy.Scan(noisy.scene_from_velo(4), 77);
  const LidarScan b = scanner_exact.Scan(exact.scene_from_velo(4), 77);
  // ~120k points: 64 beams x 2048 azimuths minus the rays into the sky.
  EXPECT_GT(a.points_velo.size(), 100000u);
  EXPECT_LE(a.points_velo.size(), static_cast<size_t>(o.lidar_beams * o.lidar_azimuth_steps));
  ASSERT_EQ(a.points_velo.size(), b.points_velo.size());  // the same rays hit (noise only moves along them)
  double sum = 0.0, sum2 = 0.0;
  double max_z = -1e9, min_z = 1e9;
  const Pose3d scene_from_velo = exact.scene_from_velo(4);
  for (size_t k = 0; k < a.points_velo.size(); ++k) {
    const double ra = a.points_velo[k].head<3>().norm(), rb = b.points_velo[k].head<3>().norm();
    sum += ra - rb;
    sum2 += (ra - rb) * (ra - rb);
    EXPECT_GE(a.points_velo[k][3], 0.0f);
    EXPECT_LE(a.points_velo[k][3], 1.0f);
    const double z_scene = (scene_from_velo * b.points_velo[k].head<3>().cast<double>()).z();
    min_z = std::min(min_z, z_scene), max_z = std::max(max_z, z_scene);
  }
  const double n = static_cast<double>(a.points_velo.size());
  EXPECT_NEAR(sum / n, 0.0, 1e-3);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 1e-3);
  // Exact points never go below the road (z = 0 in the scene); façades reach above the sensor.
  EXPECT_NEAR(min_z, 0.0, 1e-4);
  EXPECT_GT(max_z, 3.0);
}

}  // namespace
}  // namespace semap::sim
