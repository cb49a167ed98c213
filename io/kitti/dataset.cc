// Layout detection and the entry points of io/frame_source.h.
#include <filesystem>

#include "io/frame_source.h"
#include "io/kitti/internal/sequence_source.h"

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

std::unique_ptr<internal::SequenceSource> Open(const fs::path& path, const FrameSourceOptions& options) {
  options.Check();
  std::error_code ec;
  if (!fs::is_directory(path, ec)) DetectLayout(path);  // throws the missing-folder / not-a-folder error
  const DatasetLayout layout = options.layout == DatasetLayout::kAuto ? DetectLayout(path) : options.layout;
  switch (layout) {
    case DatasetLayout::kKittiRaw:
      return internal::OpenKittiRaw(path, options);
    case DatasetLayout::kKittiOdometry:
      return internal::OpenKittiOdometry(path, options);
    case DatasetLayout::kKittiStereo2015:
      return internal::OpenKittiStereo2015(path, options);
    case DatasetLayout::kAuto:
      break;
  }
  throw FileError(path, "unknown dataset layout");
}

}  // namespace

DatasetLayout DetectLayout(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw FileError(path, "dataset folder not found");
  if (!fs::is_directory(path, ec)) throw FileError(path, "not a folder (expected a dataset folder)");
  if (IsStereo2015(path)) return DatasetLayout::kKittiStereo2015;
  if (IsOdometry(path)) return DatasetLayout::kKittiOdometry;
  if (internal::FindRawDrive(path)) return DatasetLayout::kKittiRaw;
  throw FileError(path,
                  "cannot detect the dataset layout: expected a KITTI raw drive (image_02/data) or its date "
                  "folder, an odometry sequence (calib.txt + image_0|image_2, or sequences/NN) or a "
                  "stereo-2015 folder (image_2 + calib_cam_to_cam.txt)");
}

std::unique_ptr<FrameSource> OpenFrameSource(const fs::path& path, const FrameSourceOptions& options) {
  return Open(path, options);
}

SequenceInfo DescribeDataset(const fs::path& path, const FrameSourceOptions& options) {
  return Open(path, options)->info();
}

}  // namespace semap::io
