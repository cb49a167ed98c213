// Layout detection and the entry points of io/frame_source.h.
#include <algorithm>
#include <filesystem>

#include "io/frame_source.h"
#include "io/kitti/internal/sequence_source.h"
#include "io/sfm/strecha.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

bool IsOdometry(const fs::path& p) {
  if (fs::is_directory(p / "sequences")) return true;
  return fs::exists(p / "calib.txt") && (fs::is_directory(p / "image_0") || fs::is_directory(p / "image_2"));
}

bool IsStereo2015(const fs::path& p) {
  return fs::is_directory(p / "image_2") && fs::exists(p / "calib_cam_to_cam.txt");
}

std::unique_ptr<FrameSource> Open(const fs::path& path, const FrameSourceOptions& options) {
  options.Check();
  std::error_code ec;
  if (!fs::is_directory(path, ec)) DetectLayout(path);  // throws the missing-folder / not-a-folder error
  const DatasetLayout layout = options.layout == DatasetLayout::kAuto ? DetectLayout(path) : options.layout;
  switch (layout) {
    case DatasetLayout::kKittiRaw:
      return kitti_internal::OpenKittiRaw(path, options);
    case DatasetLayout::kKittiOdometry:
      return kitti_internal::OpenKittiOdometry(path, options);
    case DatasetLayout::kKittiStereo2015:
      return kitti_internal::OpenKittiStereo2015(path, options);
    case DatasetLayout::kStrecha:
      return OpenStrechaSource(path, options);
    case DatasetLayout::kAuto:
      break;
  }
  throw FileError(path, "unknown dataset layout");
}

// The selected frames read options.loops times (see OpenFrameSource). Each pass re-opens the dataset.
class LoopedSource : public FrameSource {
 public:
  LoopedSource(fs::path path, const FrameSourceOptions& options, std::unique_ptr<FrameSource> first)
      : path_(std::move(path)), options_(options), source_(std::move(first)) {
    id_span_ = source_->info().last_frame_id - source_->info().first_frame_id + 1;
    pass_frames_ = source_->size();
  }

  DatasetLayout layout() const override { return source_->layout(); }
  std::int64_t size() const override { return pass_frames_ * options_.loops; }
  const ClassMap& class_map() const override { return source_->class_map(); }
  const SequenceInfo& info() const override { return source_->info(); }

  std::optional<Frame> Next() override {
    while (true) {
      std::optional<Frame> frame;
      try {
        frame = source_->Next();
      } catch (const FrameError& e) {
        if (pass_ == 0) throw;
        throw FrameError(e.frame_id() + pass_ * id_span_,
                         "pass " + std::to_string(pass_ + 1) + ": " + e.what());
      }
      if (frame) return Shifted(std::move(*frame));
      if (pass_ + 1 >= options_.loops) return std::nullopt;
      StartNextPass();
    }
  }

 private:
  Frame Shifted(Frame f) {
    if (pass_ == 0) Record(f);
    f.id += pass_ * id_span_;
    f.timestamp_s += time_offset_s_;
    if (f.world_from_cam) {
      f.world_from_cam =
          Pose3d(Eigen::Translation3d(static_cast<double>(pass_) * shift_)) * *f.world_from_cam;
    }
    return f;
  }

  // The first pass's camera track (frames that were read and have a pose).
  void Record(const Frame& f) {
    if (!first_t_s_) first_t_s_ = f.timestamp_s;
    last_t_s_ = f.timestamp_s;
    if (!f.world_from_cam) return;
    const Eigen::Vector3d c = f.world_from_cam->translation();
    if (!first_pos_) {
      first_pos_ = c;
      min_ = max_ = c;
    } else {
      path_m_ += (c - last_pos_).norm();
      min_ = min_.cwiseMin(c);
      max_ = max_.cwiseMax(c);
    }
    last_pos_ = c;
  }

  void StartNextPass() {
    const double period_s = options_.default_frame_period_s;
    const double duration_s = first_t_s_ ? last_t_s_ - *first_t_s_ : 0.0;
    double jump_s = period_s;
    if (first_pos_) {
      if (pass_ == 0) {
        Eigen::Index axis = 0;
        const Eigen::Vector3d extent = max_ - min_;
        extent.maxCoeff(&axis);
        shift_ = Eigen::Vector3d::Unit(axis) * (extent[axis] + options_.loop_gap_m);
      }
      const double jump_m = (*first_pos_ + shift_ - last_pos_).norm();
      const double mean_speed_mps = duration_s > 0.0 ? path_m_ / duration_s : 0.0;
      if (mean_speed_mps > 0.0) jump_s = std::max(period_s, jump_m / mean_speed_mps);
    }
    time_offset_s_ += duration_s + jump_s;
    ++pass_;
    FrameSourceOptions one_pass = options_;
    one_pass.loops = 1;
    source_ = Open(path_, one_pass);
  }

  fs::path path_;
  FrameSourceOptions options_;
  std::unique_ptr<FrameSource> source_;
  std::int64_t id_span_ = 0;
  std::int64_t pass_frames_ = 0;
  std::int64_t pass_ = 0;
  double time_offset_s_ = 0.0;
  Eigen::Vector3d shift_ = Eigen::Vector3d::Zero();
  // First pass track.
  std::optional<double> first_t_s_;
  double last_t_s_ = 0.0;
  std::optional<Eigen::Vector3d> first_pos_;
  Eigen::Vector3d last_pos_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d min_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_ = Eigen::Vector3d::Zero();
  double path_m_ = 0.0;
};

}  // namespace

DatasetLayout DetectLayout(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw FileError(path, "dataset folder not found");
  if (!fs::is_directory(path, ec)) throw FileError(path, "not a folder (expected a dataset folder)");
  if (IsStrechaSet(path)) return DatasetLayout::kStrecha;
  if (IsStereo2015(path)) return DatasetLayout::kKittiStereo2015;
  if (IsOdometry(path)) return DatasetLayout::kKittiOdometry;
  if (kitti_internal::FindRawDrive(path)) return DatasetLayout::kKittiRaw;
  throw FileError(path,
                  "cannot detect the dataset layout: expected a KITTI raw drive (image_02/data) or its date "
                  "folder, an odometry sequence (calib.txt + image_0|image_2, or sequences/NN), a "
                  "stereo-2015 folder (image_2 + calib_cam_to_cam.txt) or a Strecha multi-view set "
                  "(images + gt_dense_cameras)");
}

std::unique_ptr<FrameSource> OpenFrameSource(const fs::path& path, const FrameSourceOptions& options) {
  auto source = Open(path, options);
  if (options.loops == 1) return source;
  return std::make_unique<LoopedSource>(path, options, std::move(source));
}

SequenceInfo DescribeDataset(const fs::path& path, const FrameSourceOptions& options) {
  return Open(path, options)->info();
}

}  // namespace semap::io
