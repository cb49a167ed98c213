#include "engine/sim/camera_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgproc.hpp>

#include "engine/sim/synthetic_sequence.h"

namespace semap::sim {
namespace {

SynthOptions Opts() {
  SynthOptions o;
  o.preset = ScenePreset::kMixed;
  o.num_frames = 12;
  o.seed = 11;
  return o;
}

// Rendered depth and labels equal an exact ray cast against the scene mesh through each pixel centre.
TEST(CameraRenderer, DepthAndLabelsAgreeWithRayCastScene) {
  const SyntheticSequence seq(Opts());
  const CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& cal = seq.rig().calibration;
  for (int frame : {0, 11}) {
    const Pose3d scene_from_cam = seq.scene_from_cam2(frame);
    const CameraImage img = renderer.RenderGeometry(cal, scene_from_cam);
    int checked = 0, depth_ok = 0, label_ok = 0, sky_ok = 0, sky = 0;
    for (int y = 0; y < cal.height_px; y += 3) {
      for (int x = 0; x < cal.width_px; x += 3) {
        const Eigen::Vector3d ray((x - cal.cx_px) / cal.fx_px, (y - cal.cy_px) / cal.fy_px, 1.0);
        const auto hit = seq.bvh().Intersect(scene_from_cam.translation(), scene_from_cam.linear() * ray,
                                             seq.options().near_m, 1e6);
        const float z = img.depth_m.at<float>(y, x);
        if (!hit) {
          ++sky;
          sky_ok += z == 0.0f && img.labels.at<std::uint8_t>(y, x) == label::kSky;
          continue;
        }
        ++checked;
        // t is the camera z because the ray has unit z.
        depth_ok += std::abs(z - hit->t) <= 1e-3 + 1e-6 * hit->t;
        label_ok += img.labels.at<std::uint8_t>(y, x) == seq.scene().labels[hit->triangle];
      }
    }
    ASSERT_GT(checked, 30000);
    // Only pixels whose centre lies exactly on an edge between two surfaces may differ.
    EXPECT_GT(depth_ok, 0.998 * checked) << "frame " << frame;
    EXPECT_GT(label_ok, 0.998 * checked) << "frame " << frame;
    EXPECT_GT(sky_ok, 0.998 * sky) << "frame " << frame;
  }
}

TEST(CameraRenderer, ColourRenderHasTheSameGeometryAndIsDeterministic) {
  const SyntheticSequence seq(Opts());
  const CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& cal = seq.rig().calibration;
  const CameraImage geo = renderer.RenderGeometry(cal, seq.scene_from_cam2(3));
  const CameraImage a = renderer.Render(cal, seq.scene_from_cam2(3), {1.0, 42});
  const CameraImage b = renderer.Render(cal, seq.scene_from_cam2(3), {1.0, 42});
  const CameraImage c = renderer.Render(cal, seq.scene_from_cam2(3), {1.0, 43});
  EXPECT_EQ(cv::norm(geo.depth_m, a.depth_m, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(geo.labels, a.labels, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.color, b.color, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.color, c.color, cv::NORM_L1), 0.0);  // the noise seed matters
  // Texture everywhere: the local contrast of the ground and walls is far above zero.
  cv::Mat gray;
  cv::cvtColor(a.color, gray, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::mean(gray)[0], 60.0);
  EXPECT_LT(cv::mean(gray)[0], 200.0);
}

// Samples `img` (CV_8UC3) bilinearly at (x, y).
cv::Vec3f Bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  auto at = [&](int xx, int yy) { return cv::Vec3f(img.at<cv::Vec3b>(yy, xx)); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

// Median absolute colour difference between left pixels and the right image at x - (disparity + offset),
// over textured left pixels (horizontal gradient above `min_gradient` grey levels) visible in the right view
// (the right depth at the warped pixel equals the left depth).
double MedianWarpError(const SyntheticFrame& f, const StereoCalibration& cal, double gain_ratio,
                       double offset, double min_gradient) {
  std::vector<double> err;
  for (int y = 2; y < cal.height_px - 2; y += 2) {
    for (int x = 2; x < cal.width_px - 2; x += 2) {
      const float z = f.left.depth_m.at<float>(y, x);
      if (z <= 0.0f) continue;
      const cv::Vec3f gx =
          cv::Vec3f(f.left.color.at<cv::Vec3b>(y, x + 1)) - cv::Vec3f(f.left.color.at<cv::Vec3b>(y, x - 1));
      if ((std::abs(gx[0]) + std::abs(gx[1]) + std::abs(gx[2])) / 3.0 < min_gradient) continue;
      const double xr = x - cal.DisparityFromDepth(z) - offset;
      if (xr < 1.0 || xr > cal.width_px - 2.0) continue;
      const float zr = f.right.depth_m.at<float>(y, static_cast<int>(std::lround(xr)));
      if (std::abs(zr - z) > 0.01f * z) continue;  // occluded in the right view
      const cv::Vec3f l = cv::Vec3f(f.left.color.at<cv::Vec3b>(y, x));
      const cv::Vec3f r = Bilinear(f.right.color, xr, y) / gain_ratio;
      err.push_back((std::abs(l[0] - r[0]) + std::abs(l[1] - r[1]) + std::abs(l[2] - r[2])) / 3.0);
    }
  }
  EXPECT_GT(err.size(), 3000u);
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  return err[err.size() / 2];
}

TEST(CameraRenderer, GroundTruthDisparityWarpsLeftOntoRight) {
  SynthOptions o = Opts();
  o.vignetting = 0.0;  // position-dependent brightness would differ between x and x - d
  const SyntheticSequence seq(o);
  const SyntheticFrame f = seq.RenderFrame(5);
  const StereoCalibration& cal = seq.rig().calibration;
  // As generated (noise, blur, exposure difference compensated): the GT warp matches up to the noise of two
  // images (|N(0, sqrt(2) sigma)| has median 0.95 sigma), texture interpolation and 8-bit rounding.
  const double noisy = MedianWarpError(f, cal, o.right_exposure_gain, 0.0, 0.0);
  EXPECT_LT(noisy, 0.95 * o.image_noise_sigma + 1.5);
  // On textured pixels a disparity wrong by 1 or 2 px matches worse.
  const double textured = MedianWarpError(f, cal, o.right_exposure_gain, 0.0, 12.0);
  for (double offset : {-2.0, -1.0, 1.0, 2.0}) {
    EXPECT_GT(MedianWarpError(f, cal, o.right_exposure_gain, offset, 12.0), textured + 1.0) << offset;
  }
  // Without noise and blur: the matching error is minimal exactly at the ground truth, symmetric, and small.
  o.image_noise_sigma = 0.0;
  o.blur_sigma_px = 0.0;
  const SyntheticSequence clean(o);
  const SyntheticFrame cf = clean.RenderFrame(5);
  std::map<double, double> cost;
  for (double offset : {-1.0, -0.5, -0.2, 0.0, 0.2, 0.5, 1.0}) {
    cost[offset] = MedianWarpError(cf, cal, o.right_exposure_gain, offset, 0.0);
    std::printf("clean warp offset %+.1f px: median error %.3f grey levels\n", offset, cost[offset]);
  }
  EXPECT_LT(cost[0.0], 0.5);
  EXPECT_LT(cost[0.0], cost[-0.2]);
  EXPECT_LT(cost[0.0], cost[0.2]);
  EXPECT_LT(cost[0.2], cost[0.5]);
  EXPECT_LT(cost[-0.2], cost[-0.5]);
  EXPECT_LT(cost[0.5], cost[1.0]);
  EXPECT_LT(cost[-0.5], cost[-1.0]);
  EXPECT_NEAR(cost[-0.5], cost[0.5], 0.2 * (cost[0.5] - cost[0.0]));
}

}  // namespace
}  // namespace semap::sim
