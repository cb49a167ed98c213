#include "engine/sim/synthetic_sequence.h"

#include <cmath>

#include "engine/core/check.h"
#include "engine/sim/internal/random.h"

namespace semap::sim {
namespace {

// Period (frames) of the slow exposure drift.
constexpr double kExposurePeriodFrames = 73.0;
// Independent noise streams per frame.
enum Stream : std::uint64_t { kLeftNoise = 1, kRightNoise = 2, kLidarNoise = 3, kExposure = 4 };

std::uint64_t StreamSeed(std::uint64_t seed, int frame, Stream s) {
  return sim_internal::HashCombine(sim_internal::HashCombine(seed, static_cast<std::uint64_t>(frame)), s);
}

}  // namespace

SyntheticSequence::SyntheticSequence(const SynthOptions& options)
    : options_(options), rig_(SensorRig::KittiLike(options)) {
  options_.Check();
  trajectory_ = std::make_unique<Trajectory>(Trajectory::Generate(options_, rig_.imu_height_m));
  scene_ = std::make_unique<Scene>(BuildScene(options_, *trajectory_));
  bvh_ = std::make_unique<TriangleBvh>(*scene_);
  renderer_ = std::make_unique<CameraRenderer>(*scene_, options_);
  scanner_ = std::make_unique<LidarScanner>(*scene_, *bvh_, options_);
}

SyntheticSequence::~SyntheticSequence() = default;

Pose3d SyntheticSequence::scene_from_velo(int frame) const {
  return scene_from_imu(frame) * rig_.velo_from_imu().inverse();
}
Pose3d SyntheticSequence::scene_from_cam2(int frame) const {
  return scene_from_imu(frame) * rig_.cam2_from_imu().inverse();
}
Pose3d SyntheticSequence::scene_from_cam3(int frame) const {
  return scene_from_cam2(frame) * rig_.cam2_from_cam3();
}

double SyntheticSequence::ExposureGain(int frame) const {
  sim_internal::Rng rng(sim_internal::HashCombine(options_.seed, kExposure));
  const double phase = rng.Uniform(0.0, 2.0 * M_PI);
  return 1.0 + options_.exposure_variation * std::sin(2.0 * M_PI * frame / kExposurePeriodFrames + phase);
}

SyntheticFrame SyntheticSequence::RenderFrame(int frame) const {
  SEMAP_ASSERT(frame >= 0 && frame < num_frames(), "frame " << frame);
  SyntheticFrame f;
  f.index = frame;
  f.timestamp_s = trajectory_->timestamp_s(frame);
  const double gain = ExposureGain(frame);
  f.left = renderer_->Render(rig_.calibration, scene_from_cam2(frame),
                             {gain, StreamSeed(options_.seed, frame, kLeftNoise)});
  f.right =
      renderer_->Render(rig_.calibration, scene_from_cam3(frame),
                        {gain * options_.right_exposure_gain, StreamSeed(options_.seed, frame, kRightNoise)});
  f.scan = scanner_->Scan(scene_from_velo(frame), StreamSeed(options_.seed, frame, kLidarNoise));
  return f;
}

void LabelHistogram::Add(const cv::Mat& labels) {
  SEMAP_ASSERT(labels.type() == CV_8UC1);
  for (int y = 0; y < labels.rows; ++y) {
    const auto* row = labels.ptr<std::uint8_t>(y);
    for (int x = 0; x < labels.cols; ++x) ++counts_[row[x]];
  }
  total_ += static_cast<std::uint64_t>(labels.rows) * labels.cols;
}

void LabelHistogram::Merge(const LabelHistogram& other) {
  for (size_t k = 0; k < counts_.size(); ++k) counts_[k] += other.counts_[k];
  total_ += other.total_;
}

double LabelHistogram::RoleShare(const ClassMap& classes, ClassRole role) const {
  std::uint64_t n = 0;
  for (int id = 0; id < 256; ++id) {
    if (classes.Contains(static_cast<Label>(id)) && classes.Role(static_cast<Label>(id)) == role)
      n += counts_[id];
  }
  return total_ ? static_cast<double>(n) / total_ : 0.0;
}

}  // namespace semap::sim
