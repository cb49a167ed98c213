// Is the synthetic data as hard for stereo as real KITTI? Runs plain OpenCV SGBM (3-way, 128 disparities,
// block 5, P1 = 8*3*25, P2 = 32*3*25) on the real KITTI stereo-2015 frames in ../shared and on generated
// frames, and prints density and D1 for both.
//   D1: share of ground-truth pixels whose disparity error is > 3 px and > 5 % (missing = error);
//   density: share of ground-truth pixels with a valid SGBM disparity.
// Usage: synth_sgbm_realism [kitti_stereo2015_dir] [preset urban|vegetated|mixed] [frames] [seed]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "engine/sim/synthetic_sequence.h"

namespace {

namespace fs = std::filesystem;

// Ground truth beyond this depth is not used for generated frames (KITTI's GT comes from a Velodyne that
// reaches about as far; it also leaves the sky out).
constexpr double kMaxGtDepthM = 80.0;

struct Score {
  std::uint64_t gt = 0, valid = 0, bad = 0;
  void Add(const Score& o) { gt += o.gt, valid += o.valid, bad += o.bad; }
  double D1() const { return gt ? 100.0 * bad / gt : 0.0; }
  double Density() const { return gt ? 100.0 * valid / gt : 0.0; }
};

cv::Mat Sgbm(const cv::Mat& left, const cv::Mat& right) {
  auto sgbm = cv::StereoSGBM::create(0, 128, 5, 8 * 3 * 25, 32 * 3 * 25);
  sgbm->setMode(cv::StereoSGBM::MODE_SGBM_3WAY);
  cv::Mat disp16;
  sgbm->compute(left, right, disp16);
  return disp16;  // CV_16S, disparity * 16; invalid < 0
}

// gt: CV_32F disparity, <= 0 = no ground truth. With `labels` (CV_8UC1), also scores per label.
Score Evaluate(const cv::Mat& disp16, const cv::Mat& gt, const cv::Mat& labels = {},
               std::vector<Score>* per_label = nullptr) {
  Score s;
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) {
      const float g = gt.at<float>(y, x);
      if (!(g > 0.0f)) continue;
      Score one;
      one.gt = 1;
      const short d = disp16.at<short>(y, x);
      if (d < 0) {
        one.bad = 1;
      } else {
        one.valid = 1;
        const double err = std::abs(d / 16.0 - g);
        if (err > 3.0 && err > 0.05 * g) one.bad = 1;
      }
      s.Add(one);
      if (per_label) (*per_label)[labels.at<std::uint8_t>(y, x)].Add(one);
    }
  }
  return s;
}

}  // namespace

// Per-frame spread of a figure: is a synthetic frame's figure inside the range of the real frames'?
struct Range {
  double min = 1e9, max = -1e9;
  void Add(double v) {
    min = std::min(min, v);
    max = std::max(max, v);
  }
};

int main(int argc, char** argv) {
  const fs::path kitti = argc > 1 ? argv[1] : "../shared/data/kitti_stereo2015_subset";
  const std::string preset = argc > 2 ? argv[2] : "urban";
  const int frames = argc > 3 ? std::stoi(argv[3]) : 20;
  const std::uint64_t seed = argc > 4 ? std::stoull(argv[4]) : 1;

  Score real;
  int real_frames = 0;
  double real_d1_sum = 0.0, real_density_sum = 0.0;
  Range real_d1, real_density, synth_d1, synth_density;
  if (fs::exists(kitti / "image_2")) {
    std::vector<fs::path> names;
    for (const auto& e : fs::directory_iterator(kitti / "image_2")) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    for (const auto& n : names) {
      const cv::Mat l = cv::imread((kitti / "image_2" / n).string()),
                    r = cv::imread((kitti / "image_3" / n).string());
      const cv::Mat g16 = cv::imread((kitti / "disp_occ_0" / n).string(), cv::IMREAD_UNCHANGED);
      if (l.empty() || r.empty() || g16.empty()) continue;
      cv::Mat gt;
      g16.convertTo(gt, CV_32F, 1.0 / 256.0);
      const Score s = Evaluate(Sgbm(l, r), gt);
      real.Add(s);
      real_d1_sum += s.D1();
      real_density_sum += s.Density();
      real_d1.Add(s.D1());
      real_density.Add(s.Density());
      ++real_frames;
    }
    std::printf(
        "real KITTI stereo-2015 (%d frames, %s): D1 %.1f %%, density %.1f %% over all GT pixels; "
        "mean over frames: D1 %.1f %%, density %.1f %%\n",
        real_frames, kitti.string().c_str(), real.D1(), real.Density(),
        real_d1_sum / std::max(1, real_frames), real_density_sum / std::max(1, real_frames));
  } else {
    std::printf("real KITTI frames not found at %s\n", kitti.string().c_str());
  }

  semap::sim::SynthOptions o;
  o.preset = preset == "vegetated" ? semap::sim::ScenePreset::kVegetated
             : preset == "mixed"   ? semap::sim::ScenePreset::kMixed
                                   : semap::sim::ScenePreset::kUrban;
  o.num_frames = frames;
  o.seed = seed;
  const semap::sim::SyntheticSequence seq(o);
  const auto& cal = seq.rig().calibration;
  Score synth;
  std::vector<Score> per_label(256);
  double d1_sum = 0.0, density_sum = 0.0;
  for (int i = 0; i < seq.num_frames(); ++i) {
    const auto f = seq.RenderFrame(i);
    cv::Mat gt(f.left.depth_m.size(), CV_32F, cv::Scalar(0.0f));
    for (int y = 0; y < gt.rows; ++y) {
      for (int x = 0; x < gt.cols; ++x) {
        const float z = f.left.depth_m.at<float>(y, x);
        if (z > 0.0f && z <= kMaxGtDepthM) gt.at<float>(y, x) = static_cast<float>(cal.DisparityFromDepth(z));
      }
    }
    const Score s = Evaluate(Sgbm(f.left.color, f.right.color), gt, f.left.labels, &per_label);
    synth.Add(s);
    d1_sum += s.D1();
    density_sum += s.Density();
    synth_d1.Add(s.D1());
    synth_density.Add(s.Density());
  }
  std::printf(
      "synthetic %s (%d frames, seed %llu): D1 %.1f %%, density %.1f %% over all GT pixels; mean over "
      "frames: D1 %.1f %%, density %.1f %%\n",
      preset.c_str(), frames, static_cast<unsigned long long>(seed), synth.D1(), synth.Density(),
      d1_sum / frames, density_sum / frames);
  std::printf(
      "per-frame range: real D1 %.1f-%.1f %%, density %.1f-%.1f %%; synthetic D1 %.1f-%.1f %%, density "
      "%.1f-%.1f %%\n",
      real_d1.min, real_d1.max, real_density.min, real_density.max, synth_d1.min, synth_d1.max,
      synth_density.min, synth_density.max);
  const semap::ClassMap classes = semap::ClassMap::Cityscapes();
  for (int l = 0; l < 256; ++l) {
    if (per_label[l].gt == 0) continue;
    std::printf("  %-12s %5.1f %% of GT pixels: D1 %.1f %%, density %.1f %%\n",
                classes.Contains(l) ? classes.Get(l).name.c_str() : "?", 100.0 * per_label[l].gt / synth.gt,
                per_label[l].D1(), per_label[l].Density());
  }
  return 0;
}
