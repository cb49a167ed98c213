// KITTI stereo-2015 style folder: image_2/NNNNNN_10.png, image_3, disp_occ_0, velodyne/NNNNNN_10.bin and
// the raw-format calibration files; every frame stands alone with the camera at the origin.
#include <opencv2/imgcodecs.hpp>

#include "io/kitti/calibration.h"
#include "io/kitti/internal/sequence_source.h"

namespace semap::io::kitti_internal {
namespace {

namespace fs = std::filesystem;

class KittiStereo2015Source : public SequenceSource {
 public:
  using SequenceSource::SequenceSource;

 protected:
  std::optional<Pose3d> PoseAt(size_t) override { return Pose3d::Identity(); }
};

}  // namespace

std::unique_ptr<SequenceSource> OpenKittiStereo2015(const fs::path& path, const FrameSourceOptions& options) {
  const RawCalibration calib = ReadRawCalibration(path);
  SequenceScan scan;
  SequenceInfo& info = scan.info;
  info.layout = DatasetLayout::kKittiStereo2015;
  info.root = path;
  info.left_dir = path / "image_2";
  info.calibration = calib.stereo;
  scan.calibration_file = path / "calib_cam_to_cam.txt";
  scan.calibration_key = "P_rect_02";
  scan.right_dir = path / "image_3";
  scan.imread_flags = cv::IMREAD_COLOR;
  scan.all_frames = ListFrames(info.left_dir, std::regex(R"((\d{1,12})_10\.png)"));
  SelectFrames(options, &scan);
  if (!fs::is_directory(scan.right_dir)) throw FileError(scan.right_dir, "right image folder not found");
  // Frames are unrelated; their timestamps only order them (position × period).
  for (size_t i = 0; i < scan.frames.size(); ++i) {
    scan.timestamps_s.push_back(static_cast<double>(i) * options.default_frame_period_s);
  }
  info.has_timestamps = false;
  info.has_poses = true;  // identity: each frame is its own world
  const fs::path velo_dir = path / "velodyne";
  if (fs::is_directory(velo_dir)) {
    if (calib.cam2_from_velo) {
      info.has_velodyne = true;
      info.cam_from_velo = calib.cam2_from_velo;
      if (options.load_velodyne) scan.velodyne_dir = velo_dir;
    } else {
      info.notes.push_back("velodyne present but no calib_velo_to_cam.txt: scans not read");
    }
  }
  AttachLabels(options, {}, &scan);
  FinishInfo(&scan);
  return std::make_unique<KittiStereo2015Source>(std::move(scan));
}

}  // namespace semap::io::kitti_internal
