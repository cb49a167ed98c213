// KITTI odometry layout: ROOT/sequences/NN/{image_0,image_1 | image_2,image_3}/%06d.png, calib.txt,
// times.txt (optional), velodyne/%06d.bin; ROOT/poses/NN.txt = world_from_cam0 (3×4 row-major).
#include <opencv2/imgcodecs.hpp>

#include "io/kitti/calibration.h"
#include "io/kitti/internal/sequence_source.h"
#include "io/kitti/sequence_files.h"

namespace semap::io::kitti_internal {
namespace {

namespace fs = std::filesystem;

// Poses are few (12 numbers a frame) and read at open; images stay lazy.
class KittiOdometrySource : public SequenceSource {
 public:
  KittiOdometrySource(SequenceScan scan, std::vector<Pose3d> world_from_cam)
      : SequenceSource(std::move(scan)), world_from_cam_(std::move(world_from_cam)) {}

 protected:
  std::optional<Pose3d> PoseAt(size_t index) override {
    if (world_from_cam_.empty()) return std::nullopt;
    return world_from_cam_[index];
  }

 private:
  std::vector<Pose3d> world_from_cam_;  // one per selected frame, or none
};

// The sequence folder: `path` itself, or the only folder in path/sequences.
fs::path FindSequence(const fs::path& path) {
  const fs::path seqs = path / "sequences";
  if (!fs::is_directory(seqs)) return path;
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(seqs)) {
    if (e.is_directory()) found.push_back(e.path());
  }
  if (found.size() != 1) {
    throw FileError(seqs, "holds " + std::to_string(found.size()) +
                              " sequences; pass one sequence folder (sequences/NN)");
  }
  return found.front();
}

}  // namespace

std::unique_ptr<SequenceSource> OpenKittiOdometry(const fs::path& path, const FrameSourceOptions& options) {
  const fs::path seq = FindSequence(path);
  const bool color_present = fs::is_directory(seq / "image_2");
  bool color = options.odometry_pair == CameraPair::kColor;
  if (options.odometry_pair == CameraPair::kAuto) color = color_present;
  const OdometryCalibration calib =
      ReadOdometryCalibration(seq / "calib.txt", color ? OdometryPair::kColor : OdometryPair::kGray);

  SequenceScan scan;
  SequenceInfo& info = scan.info;
  info.layout = DatasetLayout::kKittiOdometry;
  info.root = seq;
  info.left_dir = seq / (color ? "image_2" : "image_0");
  info.calibration = calib.stereo;
  scan.calibration_file = seq / "calib.txt";
  scan.calibration_key = color ? "P2" : "P0";
  scan.right_dir = seq / (color ? "image_3" : "image_1");
  scan.imread_flags = color ? cv::IMREAD_COLOR : cv::IMREAD_GRAYSCALE;
  scan.all_frames = ListFrames(info.left_dir, std::regex(R"((\d{1,12})\.png)"));
  SelectFrames(options, &scan);
  if (!fs::is_directory(scan.right_dir)) throw FileError(scan.right_dir, "right image folder not found");

  const fs::path times = seq / "times.txt";
  if (fs::exists(times)) {
    TimestampsFromFile(ReadOdometryTimes(times), times, "times", &scan);
  } else {
    NominalTimestamps(options, &scan);
    info.notes.push_back("no times.txt: timestamps are frame id x default_frame_period_s");
  }

  // poses/NN.txt beside `sequences` (ROOT/poses/NN.txt for ROOT/sequences/NN).
  const fs::path poses_path = seq.parent_path().parent_path() / "poses" / (seq.filename().string() + ".txt");
  std::vector<Pose3d> world_from_cam;
  if (fs::exists(poses_path)) {
    const std::vector<Pose3d> world_from_cam0 =
        ReadOdometryPoses(poses_path, static_cast<size_t>(scan.frames.back().id + 1));
    const Pose3d cam0_from_cam = calib.cam_from_cam0.inverse();  // colour: T(x = -P2[0,3]/fx)
    for (const auto& f : scan.frames) world_from_cam.push_back(world_from_cam0[f.id] * cam0_from_cam);
    info.has_poses = true;
  }

  const fs::path velo_dir = seq / "velodyne";
  if (fs::is_directory(velo_dir)) {
    if (calib.cam_from_velo) {
      info.has_velodyne = true;
      info.cam_from_velo = calib.cam_from_velo;
      if (options.load_velodyne) scan.velodyne_dir = velo_dir;
    } else {
      info.notes.push_back("velodyne present but calib.txt has no Tr: scans not read");
    }
  }
  AttachLabels(options, {}, &scan);
  FinishInfo(&scan);
  return std::make_unique<KittiOdometrySource>(std::move(scan), std::move(world_from_cam));
}

}  // namespace semap::io::kitti_internal
