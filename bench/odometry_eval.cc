// semap_odometry_eval: accuracy and cost of the stereo visual odometry on a sequence with poses (KITTI
// odometry, KITTI raw, or one made by `semap synth`), the poses withheld from the odometry and used only to
// score it. Prints the relative pose error over 10-frame windows, the KITTI odometry metric (segments of
// 100-800 m where the drive is that long), the ATE after alignment, the end-point error, a diagnostic (the
// fixed rotation between the poses' camera frame and the odometry's that explains most of the 10-frame error,
// and that error with it taken out), and the odometry's CPU time per frame on one core (cv::setNumThreads(1);
// the calling thread's CPU time, not wall time).
//
// With --synth PRESET instead of a dataset, the frames of `semap synth --preset PRESET --frames N` (its
// scene, drive, turns and exposure) are rendered in memory, without the Velodyne scans and without writing
// them.
//
// Usage: semap_odometry_eval DATASET|--synth urban|vegetated|mixed [--config FILE] [--set key=value ...]
//                            [--frames N] [--poses-out FILE]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "engine/eval/trajectory_metrics.h"
#include "engine/odometry/stereo_odometry.h"
#include "engine/sim/camera_renderer.h"
#include "engine/sim/synthetic_sequence.h"
#include "io/frame_source.h"

namespace {

// Frames of a dataset, or rendered from a generated drive.
class Frames {
 public:
  virtual ~Frames() = default;
  virtual std::optional<semap::Frame> Next() = 0;
};

class DatasetFrames : public Frames {
 public:
  DatasetFrames(const std::string& dataset, const semap::io::FrameSourceOptions& input)
      : source_(semap::io::OpenFrameSource(dataset, input)) {}
  std::optional<semap::Frame> Next() override { return source_->Next(); }

 private:
  std::unique_ptr<semap::io::FrameSource> source_;
};

class SynthFrames : public Frames {
 public:
  explicit SynthFrames(const semap::sim::SynthOptions& options)
      : seq_(options), renderer_(seq_.scene(), seq_.options()) {}
  std::optional<semap::Frame> Next() override {
    if (next_ >= seq_.num_frames()) return std::nullopt;
    const int i = next_++;
    const double gain = seq_.ExposureGain(i);
    semap::Frame f;
    f.id = i;
    f.timestamp_s = seq_.trajectory().timestamp_s(i);
    f.calibration = seq_.rig().calibration;
    const auto seed = static_cast<std::uint64_t>(i);
    f.left = renderer_.Render(f.calibration, seq_.scene_from_cam2(i), {gain, 2 * seed + 1}).color;
    f.right = renderer_
                  .Render(f.calibration, seq_.scene_from_cam3(i),
                          {gain * seq_.options().right_exposure_gain, 2 * seed + 2})
                  .color;
    f.world_from_cam = seq_.world_from_cam2(i);
    return f;
  }

 private:
  semap::sim::SyntheticSequence seq_;
  semap::sim::CameraRenderer renderer_;
  int next_ = 0;
};

// The figures of one drive: the truth and the estimate per frame, and what the odometry reported.
struct Drive {
  std::vector<semap::Pose3d> truth, estimate;
  std::vector<double> cpu_ms;
  double features = 0, inliers = 0;
  int failed = 0, keyframes = 0;
  semap::DisparityOffset estimate_offset_at_end;
};

// The frames of --synth's preset (named by `*dataset` afterwards), else of the dataset folder; null (after a
// message) when neither is given.
std::unique_ptr<Frames> OpenFrames(const semap::app::Config& config, const std::string& synth, int frames,
                                   std::string* dataset) {
  if (!synth.empty()) {
    semap::sim::SynthOptions o = config.synth;
    o.preset = synth == "vegetated" ? semap::sim::ScenePreset::kVegetated
               : synth == "mixed"   ? semap::sim::ScenePreset::kMixed
                                    : semap::sim::ScenePreset::kUrban;
    if (frames > 0) o.num_frames = frames;
    o.Check();
    *dataset = "generated " + synth + " drive";
    return std::make_unique<SynthFrames>(o);
  }
  if (!dataset->empty()) return std::make_unique<DatasetFrames>(*dataset, config.input);
  std::fprintf(stderr, "give a dataset folder or --synth PRESET\n");
  return nullptr;
}

// Prints the figures so far to stderr (--report-every).
void ReportSoFar(const Drive& d) {
  const auto k = semap::KittiOdometryMetric(d.truth, d.estimate);
  const auto rel = semap::RelativeError(d.truth, d.estimate, 10);
  std::fprintf(stderr, "%zu frames: KITTI %.3f %% %.5f deg/m (%d segments); 10-frame %.3f %% %.5f deg/m\n",
               d.truth.size(), k.overall.translation_percent, k.overall.rotation_deg_per_m,
               k.overall.segments, rel.drift.translation_percent, rel.drift.rotation_deg_per_m);
}

// Runs the odometry over every frame (the first one's pose given); false (after a message) when a frame has
// no pose to score against.
bool RunOdometry(Frames& source, const semap::StereoOdometryOptions& options, int report_every,
                 bool print_offsets, Drive* d) {
  std::unique_ptr<semap::StereoOdometry> odometry;
  while (auto frame = source.Next()) {
    if (!frame->world_from_cam) {
      std::fprintf(stderr, "frame %lld has no pose: nothing to score against\n",
                   static_cast<long long>(frame->id));
      return false;
    }
    if (!odometry) {
      odometry = std::make_unique<semap::StereoOdometry>(options, frame->calibration);
      odometry->SetFirstPose(*frame->world_from_cam);
    }
    const semap::OdometryResult r = odometry->Track(frame->left, frame->right, frame->timestamp_s);
    d->truth.push_back(*frame->world_from_cam);
    d->estimate.push_back(r.world_from_cam);
    d->cpu_ms.push_back(r.cpu_ms);
    if (r.status == semap::OdometryStatus::kTracked) d->estimate_offset_at_end = r.disparity_offset;
    d->features += r.features;
    d->inliers += r.inliers;
    d->keyframes += r.keyframe;
    if (report_every > 0 && d->truth.size() % static_cast<size_t>(report_every) == 0) ReportSoFar(*d);
    if (print_offsets && r.frame_offset_sigma_px > 0.0) {
      std::printf(
          "frame %lld: disparity offset %+.3f ± %.3f px, per row %+.3f px; in use %+.3f px, %+.3f px\n",
          static_cast<long long>(frame->id), r.frame_offset.constant_px, r.frame_offset_sigma_px,
          r.frame_offset.per_row_px, r.disparity_offset.constant_px, r.disparity_offset.per_row_px);
    }
    if (r.status == semap::OdometryStatus::kBridged || r.status == semap::OdometryStatus::kRestarted) {
      ++d->failed;
      std::fprintf(stderr, "frame %lld: %s: %s\n", static_cast<long long>(frame->id),
                   semap::OdometryStatusName(r.status), r.problem.c_str());
    }
  }
  return true;
}

// The estimate in the KITTI pose format.
void WritePoses(const std::string& path, const std::vector<semap::Pose3d>& estimate) {
  std::ofstream out(path);
  for (const auto& p : estimate) {
    const Eigen::Matrix<double, 3, 4> m = p.matrix().topRows<3>();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) out << (r + c ? " " : "") << m(r, c);
    }
    out << "\n";
  }
}

// The scores of the estimate against the truth (two frames or more), and the odometry's cost.
void PrintReport(const std::string& dataset, const Drive& d, bool print_offset_at_end) {
  const size_t n = d.truth.size();
  const auto rpe = semap::RelativeError(d.truth, d.estimate, 10);
  const auto kitti = semap::KittiOdometryMetric(d.truth, d.estimate);
  const auto ate = semap::AbsoluteError(d.truth, d.estimate);
  std::vector<double> sorted = d.cpu_ms;
  std::sort(sorted.begin(), sorted.end());
  double cpu_sum = 0;
  for (double c : d.cpu_ms) cpu_sum += c;
  std::printf("%s: %zu frames, %.1f m, %d failed (bridged or restarted)\n", dataset.c_str(), n,
              ate.path_length_m, d.failed);
  std::printf(
      "RPE over 10 frames: %.3f %% translation, %.5f deg/m rotation (%d windows, mean %.1f m); "
      "RMSE %.3f m, %.3f deg\n",
      rpe.drift.translation_percent, rpe.drift.rotation_deg_per_m, rpe.drift.segments, rpe.drift.length_m,
      rpe.translation_rmse_m, rpe.rotation_rmse_deg);
  if (kitti.overall.segments > 0) {
    std::printf("KITTI metric: %.3f %% translation, %.5f deg/m rotation (%d segments)\n",
                kitti.overall.translation_percent, kitti.overall.rotation_deg_per_m, kitti.overall.segments);
    for (const auto& l : kitti.per_length) {
      std::printf("  %4.0f m: %.3f %%, %.5f deg/m (%d)\n", l.length_m, l.translation_percent,
                  l.rotation_deg_per_m, l.segments);
    }
  } else {
    std::printf("KITTI metric: the drive is shorter than 100 m\n");
  }
  std::printf(
      "ATE after alignment: RMSE %.3f m, max %.3f m; end point %.3f m (%.2f %% of the path), %.3f deg\n",
      ate.rmse_m, ate.max_m, ate.end_point_m, ate.end_point_percent, ate.end_rotation_deg);
  // A diagnostic fitted on the poses (not a score): how much of the 10-frame error one fixed rotation between
  // the poses' camera frame and the odometry's explains (engine/eval/trajectory_metrics.h).
  const auto frame_fit = semap::FitFrameRotation(d.truth, d.estimate, 10);
  std::printf(
      "fixed frame rotation that best maps the estimate's 10-frame directions onto the poses': "
      "(%+.3f, %+.3f, %+.3f) deg about the camera's x, y, z; RPE with it taken out: %.3f %% translation, "
      "%.5f deg/m rotation (diagnostic, fitted on the poses)\n",
      frame_fit.angles_deg.x(), frame_fit.angles_deg.y(), frame_fit.angles_deg.z(),
      frame_fit.relative.drift.translation_percent, frame_fit.relative.drift.rotation_deg_per_m);
  if (print_offset_at_end) {
    std::printf("disparity offset at the end: %+.3f px, per row %+.3f px\n",
                d.estimate_offset_at_end.constant_px, d.estimate_offset_at_end.per_row_px);
  }
  std::printf(
      "odometry CPU per frame (1 thread): mean %.2f ms, p50 %.2f, p95 %.2f, max %.2f; features %.0f, "
      "inliers %.0f; %d keyframes\n",
      cpu_sum / n, sorted[n / 2], sorted[std::min(n - 1, n * 95 / 100)], sorted.back(), d.features / n,
      d.inliers / n, d.keyframes);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"stereo visual odometry against a sequence's own poses"};
  std::string dataset, config_file, poses_out, synth;
  std::vector<std::string> overrides;
  int frames = 0;
  int report_every = 0;
  bool print_offsets = false;
  cli.add_option("dataset", dataset, "sequence folder");
  cli.add_option("--synth", synth, "render this preset's generated drive (urban, vegetated, mixed) instead");
  cli.add_option("--config", config_file, "YAML config");
  cli.add_option("--set", overrides, "section.key=value overrides");
  cli.add_option("--frames", frames, "frames to use (0 = all)");
  cli.add_option("--poses-out", poses_out, "write the estimate here (KITTI pose format)");
  cli.add_option(
      "--report-every", report_every,
      "every this many frames, print the figures so far to stderr (long drives; 0 = only at the end)");
  cli.add_flag("--offsets", print_offsets,
               "print each frame's disparity offset estimate (with odometry.estimate_disparity_offset)");
  CLI11_PARSE(cli, argc, argv);

  cv::setNumThreads(1);
  semap::app::Config config = semap::app::LoadConfig(config_file, overrides);
  config.input.load_velodyne = false;
  config.input.load_labels = false;
  if (frames > 0) config.input.max_frames = frames;
  std::unique_ptr<Frames> source = OpenFrames(config, synth, frames, &dataset);
  if (!source) return 2;
  Drive drive;
  if (!RunOdometry(*source, config.odometry, report_every, print_offsets, &drive)) return 1;
  if (drive.truth.size() < 2) {
    std::fprintf(stderr, "fewer than 2 frames\n");
    return 1;
  }
  if (!poses_out.empty()) WritePoses(poses_out, drive.estimate);
  PrintReport(dataset, drive, config.odometry.estimate_disparity_offset != semap::OffsetEstimate::kOff);
  return 0;
}
