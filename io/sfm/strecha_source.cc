// A Strecha set streamed as frames (DatasetLayout::kStrecha): io/sfm/strecha.h's views, one frame each.
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "engine/depth/view_selection.h"
#include "io/kitti/internal/sequence_source.h"
#include "io/labels/label_images.h"
#include "io/sfm/strecha.h"

namespace semap::io {
namespace {

namespace fs = std::filesystem;

// K(0, 1), the skew, must be 0 within this many px: the frames' pinhole model has none.
constexpr double kMaxSkewPx = 1e-6;

StereoCalibration Intrinsics(const StrechaView& view, double baseline_m) {
  StereoCalibration c;
  c.fx_px = view.K(0, 0);
  c.fy_px = view.K(1, 1);
  c.cx_px = view.K(0, 2);
  c.cy_px = view.K(1, 2);
  c.width_px = view.width_px;
  c.height_px = view.height_px;
  c.baseline_m = baseline_m;
  return c;
}

// Each view's neighbours (indices into the whole set, nearest first) and the distance to the nearest.
struct Neighbourhood {
  std::vector<std::size_t> views;
  double nearest_m = 0.0;
};

std::vector<Neighbourhood> Neighbourhoods(const std::vector<StrechaView>& set, int count) {
  std::vector<Pose3d> poses;
  for (const StrechaView& v : set) poses.push_back(v.world_from_cam);
  ViewSelectionOptions selection;
  selection.max_views = count;
  std::vector<Neighbourhood> out(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    out[i].views = SelectNeighbourViews(poses[i], poses, selection);
    if (!out[i].views.empty()) {
      out[i].nearest_m = (poses[out[i].views.front()].translation() - poses[i].translation()).norm();
    }
  }
  return out;
}

class StrechaSource final : public FrameSource {
 public:
  StrechaSource(std::vector<StrechaView> set, kitti_internal::SequenceScan scan,
                std::vector<Neighbourhood> neighbourhoods, std::vector<std::size_t> selected)
      : set_(std::move(set)),
        scan_(std::move(scan)),
        neighbourhoods_(std::move(neighbourhoods)),
        selected_(std::move(selected)) {}

  DatasetLayout layout() const override { return DatasetLayout::kStrecha; }
  std::int64_t size() const override { return static_cast<std::int64_t>(selected_.size()); }
  const ClassMap& class_map() const override { return scan_.info.class_map; }
  const SequenceInfo& info() const override { return scan_.info; }

  std::optional<Frame> Next() override {
    if (next_ >= selected_.size()) return std::nullopt;
    const std::size_t k = next_++;  // advance first: a bad frame is skipped, the next call reads the next
    return kitti_internal::ReadAsFrame(scan_.frames[k].id, [&] { return ReadFrame(k); });
  }

 private:
  Frame ReadFrame(std::size_t k) {
    const std::size_t index = selected_[k];
    const StrechaView& view = set_[index];
    const Neighbourhood& around = neighbourhoods_[index];
    Frame f;
    f.id = scan_.frames[k].id;
    f.timestamp_s = scan_.timestamps_s[k];
    f.left = kitti_internal::ReadImage(view.image, cv::IMREAD_COLOR, "image");
    f.calibration = Intrinsics(view, around.nearest_m);
    f.world_from_cam = view.world_from_cam;
    for (const std::size_t n : around.views) {
      CalibratedView neighbour;
      neighbour.frame_id = static_cast<std::int64_t>(n);
      neighbour.image = kitti_internal::ReadImage(set_[n].image, cv::IMREAD_GRAYSCALE, "neighbour image");
      neighbour.K = set_[n].K;
      neighbour.world_from_cam = set_[n].world_from_cam;
      f.neighbour_views.push_back(std::move(neighbour));
    }
    if (!scan_.labels_dir.empty()) {
      f.labels = ReadLabelImage(scan_.labels_dir / (scan_.frames[k].stem + ".png"), cv::Size());
    }
    return f;
  }

  std::vector<StrechaView> set_;
  kitti_internal::SequenceScan scan_;
  std::vector<Neighbourhood> neighbourhoods_;
  std::vector<std::size_t> selected_;  // indices into set_ of the frames read, in order
  std::size_t next_ = 0;
};

}  // namespace

bool IsStrechaSet(const fs::path& root) {
  std::error_code ec;
  return fs::is_directory(root / "images", ec) && fs::is_directory(root / "gt_dense_cameras", ec);
}

std::unique_ptr<FrameSource> OpenStrechaSource(const fs::path& root, const FrameSourceOptions& options) {
  options.Check();
  std::vector<StrechaView> set = ReadStrechaSet(root);
  for (const StrechaView& view : set) {
    if (std::abs(view.K(0, 1)) > kMaxSkewPx) {
      throw FileError(view.camera_file, "line 1: K has a skew of " + std::to_string(view.K(0, 1)) +
                                            " px; semap's pinhole model has none");
    }
  }
  kitti_internal::SequenceScan scan;
  SequenceInfo& info = scan.info;
  info.layout = DatasetLayout::kStrecha;
  info.root = root;
  info.left_dir = root / "images";
  for (std::size_t i = 0; i < set.size(); ++i) {
    scan.all_frames.push_back({static_cast<std::int64_t>(i), set[i].image.stem().string()});
  }
  kitti_internal::SelectFrames(options, &scan);
  kitti_internal::NominalTimestamps(options, &scan);
  kitti_internal::AttachLabels(options, root / "labels", &scan);
  std::vector<std::size_t> selected;
  for (const auto& entry : scan.frames) selected.push_back(static_cast<std::size_t>(entry.id));
  std::vector<Neighbourhood> neighbourhoods = Neighbourhoods(set, options.neighbour_views);
  const StrechaView& first = set[selected.front()];
  info.num_frames = static_cast<std::int64_t>(selected.size());
  info.num_frames_on_disk = static_cast<std::int64_t>(set.size());
  info.first_frame_id = scan.frames.front().id;
  info.last_frame_id = scan.frames.back().id;
  info.color = true;
  info.calibration = Intrinsics(first, neighbourhoods[selected.front()].nearest_m);
  info.has_poses = true;
  info.has_timestamps = false;
  info.notes.push_back("a multi-view set without a stereo pair: each frame's depth is swept against its " +
                       std::to_string(options.neighbour_views) +
                       " nearest views (input.neighbour_views); the calibration shown is the first frame's, "
                       "its baseline the distance to that frame's nearest view");
  for (const std::size_t index : selected) {
    if (neighbourhoods[index].views.empty()) {
      info.notes.push_back("view " + set[index].image.filename().string() +
                           " has no neighbour view looking the same way: its frame gives no depth");
    }
  }
  return std::make_unique<StrechaSource>(std::move(set), std::move(scan), std::move(neighbourhoods),
                                         std::move(selected));
}

}  // namespace semap::io
