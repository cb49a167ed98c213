// KITTI raw layout: ROOT/DATE/DATE_drive_NNNN_sync/{image_02,image_03}/data/%010d.png,
// velodyne_points/data/%010d.bin, oxts/data/%010d.txt, timestamps.txt per folder; calibration in ROOT/DATE.
#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "io/kitti/calibration.h"
#include "io/kitti/internal/sequence_source.h"
#include "io/kitti/oxts.h"
#include "io/kitti/sequence_files.h"

namespace semap::io::kitti_internal {
namespace {

namespace fs = std::filesystem;

bool IsDrive(const fs::path& p) { return fs::is_directory(p / "image_02" / "data"); }

// Subfolders of `dir` that are drives.
std::vector<fs::path> DrivesIn(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_directory() && IsDrive(e.path())) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

class KittiRawSource : public SequenceSource {
 public:
  KittiRawSource(SequenceScan scan, fs::path oxts_dir, std::optional<OxtsPoseConverter> converter,
                 Pose3d imu_from_cam2, fs::path missing_calibration)
      : SequenceSource(std::move(scan)),
        oxts_dir_(std::move(oxts_dir)),
        converter_(std::move(converter)),
        imu_from_cam2_(imu_from_cam2),
        missing_calibration_(std::move(missing_calibration)) {}

 protected:
  // world_from_cam2_i = world_from_imu_i · cam2_from_imu⁻¹, from the frame's own OXTS file.
  std::optional<Pose3d> PoseAt(size_t index) override {
    if (!missing_calibration_.empty()) {
      // The drive has poses, but they cannot be used: say which file is missing rather than "no pose".
      throw FileError(missing_calibration_, "calibration file not found: the OXTS poses (oxts/data) need it");
    }
    if (!converter_) return std::nullopt;
    const OxtsPacket packet = ReadOxtsFile(oxts_dir_ / (scan().frames[index].stem + ".txt"));
    return converter_->WorldFromImu(packet) * imu_from_cam2_;
  }

 private:
  fs::path oxts_dir_;
  std::optional<OxtsPoseConverter> converter_;
  Pose3d imu_from_cam2_;
  fs::path missing_calibration_;  // set when oxts/data is present but a calibration file it needs is not
};

}  // namespace

std::optional<fs::path> FindRawDrive(const fs::path& path) {
  if (IsDrive(path)) return path;
  std::vector<fs::path> drives = DrivesIn(path);
  if (drives.empty()) {
    // ROOT/DATE/drive: look one level deeper.
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(path, ec)) {
      if (!e.is_directory()) continue;
      const auto inner = DrivesIn(e.path());
      drives.insert(drives.end(), inner.begin(), inner.end());
    }
  }
  if (drives.empty()) return std::nullopt;
  if (drives.size() > 1) {
    std::string names;
    for (const auto& d : drives) names += (names.empty() ? "" : ", ") + d.filename().string();
    throw FileError(path, "holds " + std::to_string(drives.size()) + " KITTI raw drives (" + names +
                              "); pass one drive folder");
  }
  return drives.front();
}

std::unique_ptr<SequenceSource> OpenKittiRaw(const fs::path& path, const FrameSourceOptions& options) {
  const auto drive = FindRawDrive(path);
  if (!drive) throw FileError(path, "not a KITTI raw drive (no image_02/data)");
  // Calibration sits in the date folder; accept it in the drive folder too.
  fs::path calib_dir = drive->parent_path();
  if (!fs::exists(calib_dir / "calib_cam_to_cam.txt") && fs::exists(*drive / "calib_cam_to_cam.txt")) {
    calib_dir = *drive;
  }
  const RawCalibration calib = ReadRawCalibration(calib_dir);

  SequenceScan scan;
  SequenceInfo& info = scan.info;
  info.layout = DatasetLayout::kKittiRaw;
  info.root = *drive;
  info.left_dir = *drive / "image_02" / "data";
  info.calibration = calib.stereo;
  scan.calibration_file = calib_dir / "calib_cam_to_cam.txt";
  scan.calibration_key = "P_rect_02";
  scan.right_dir = *drive / "image_03" / "data";
  scan.imread_flags = cv::IMREAD_COLOR;
  scan.all_frames = ListFrames(info.left_dir, std::regex(R"((\d{1,12})\.png)"));
  SelectFrames(options, &scan);
  if (!fs::is_directory(scan.right_dir)) throw FileError(scan.right_dir, "right image folder not found");

  // Timestamps of the left camera; line k belongs to frame k.
  const fs::path stamps = *drive / "image_02" / "timestamps.txt";
  if (fs::exists(stamps)) {
    TimestampsFromFile(ReadKittiTimestamps(stamps), stamps, "timestamps", &scan);
  } else {
    NominalTimestamps(options, &scan);
    info.notes.push_back("no image_02/timestamps.txt: timestamps are frame id x default_frame_period_s");
  }

  const fs::path velo_dir = *drive / "velodyne_points" / "data";
  if (fs::is_directory(velo_dir)) {
    if (calib.cam2_from_velo) {
      info.has_velodyne = true;
      info.cam_from_velo = calib.cam2_from_velo;
      if (options.load_velodyne) scan.velodyne_dir = velo_dir;
    } else {
      info.notes.push_back("velodyne_points present but no calib_velo_to_cam.txt: scans not read");
    }
  }

  // Poses from OXTS: scale and world frame from the first frame on disk.
  const fs::path oxts_dir = *drive / "oxts" / "data";
  std::optional<OxtsPoseConverter> converter;
  Pose3d imu_from_cam2 = Pose3d::Identity();
  fs::path missing_calibration;
  if (fs::is_directory(oxts_dir)) {
    if (calib.cam2_from_imu) {
      converter.emplace(ReadOxtsFile(oxts_dir / (scan.all_frames.front().stem + ".txt")));
      imu_from_cam2 = calib.cam2_from_imu->inverse();
      info.has_poses = true;
    } else {
      missing_calibration =
          calib_dir / (calib.cam2_from_velo ? "calib_imu_to_velo.txt" : "calib_velo_to_cam.txt");
      info.notes.push_back("oxts present but " + missing_calibration.string() + " missing: no poses");
    }
  }
  AttachLabels(options, *drive / "semantic" / "data", &scan);
  FinishInfo(&scan);
  return std::make_unique<KittiRawSource>(std::move(scan), oxts_dir, std::move(converter), imu_from_cam2,
                                          std::move(missing_calibration));
}

}  // namespace semap::io::kitti_internal
