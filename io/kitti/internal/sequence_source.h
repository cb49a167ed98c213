// Shared machinery of the KITTI frame sources (not API): what a layout scanner finds on disk, and the
// streaming base class that reads one frame per Next().
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "io/frame_source.h"

namespace semap::io::kitti_internal {

struct FrameEntry {
  std::int64_t id = 0;  // number in the file name
  std::string stem;     // file name without extension ("0000000003", "000002_10")
};

// Everything a layout scanner finds. Paths of a frame's files are `dir / (stem + ext)`.
struct SequenceScan {
  SequenceInfo info;
  std::filesystem::path right_dir;
  std::filesystem::path velodyne_dir;      // empty = not read
  std::filesystem::path labels_dir;        // empty = none
  std::filesystem::path calibration_file;  // where info.calibration was read, and its key (for errors)
  std::string calibration_key;
  int imread_flags = 0;                // cv::IMREAD_COLOR or cv::IMREAD_GRAYSCALE
  std::vector<FrameEntry> all_frames;  // every left image on disk, by id
  std::vector<FrameEntry> frames;      // the selected ones
  std::vector<double> timestamps_s;    // one per selected frame, seconds since the first frame on disk
};

// The files of `dir` whose name matches `pattern` (one capture group: the frame number), sorted by id.
// Throws FileError(dir) when the folder is missing.
std::vector<FrameEntry> ListFrames(const std::filesystem::path& dir, const std::regex& pattern);

// Fills scan->frames from scan->all_frames (id >= first_frame, at most max_frames); throws FileError(dir)
// when nothing is left.
void SelectFrames(const FrameSourceOptions& options, SequenceScan* scan);

// Timestamps by id × period (no timestamps on disk).
void NominalTimestamps(const FrameSourceOptions& options, SequenceScan* scan);

// Timestamps of the selected frames from a times file already read (line k = frame k), relative to the first
// frame on disk. Throws FileError naming `path` when it has too few lines; `noun` names its lines in the
// message ("timestamps", "times").
void TimestampsFromFile(const std::vector<double>& times_s, const std::filesystem::path& path,
                        const std::string& noun, SequenceScan* scan);

// Labels: options.labels_dir, else `default_dir` when it exists (none when options.load_labels is off);
// loads the class map. Sets labels_dir and the info's label fields.
void AttachLabels(const FrameSourceOptions& options, const std::filesystem::path& default_dir,
                  SequenceScan* scan);

// Image size from the first selected left image's PNG header (throws FileError when unreadable).
cv::Size PngSize(const std::filesystem::path& path);

// Fills frame ids, counts and image size of scan->info from the rest of the scan, and checks that the
// calibration fits that image size (CheckIntrinsicsFitImage; throws FileError naming the calibration file).
void FinishInfo(SequenceScan* scan);

// Reads an image (cv::imread `flags`); throws FileError naming the file and `what` ("left image") when it is
// missing or cannot be decoded.
cv::Mat ReadImage(const std::filesystem::path& path, int flags, const char* what);

// `read()`'s frame; a FileError or an OpenCV error it throws becomes FrameError(frame_id, "frame N: ...").
Frame ReadAsFrame(std::int64_t frame_id, const std::function<Frame()>& read);

// Reads frames one at a time. A frame that cannot be read throws FrameError; the next Next() goes on.
class SequenceSource : public FrameSource {
 public:
  explicit SequenceSource(SequenceScan scan);

  DatasetLayout layout() const override { return scan_.info.layout; }
  std::int64_t size() const override { return static_cast<std::int64_t>(scan_.frames.size()); }
  std::optional<Frame> Next() override;
  const ClassMap& class_map() const override { return scan_.info.class_map; }
  const SequenceInfo& info() const override { return scan_.info; }

 protected:
  // Pose of the left camera of selected frame `index`; nullopt when unknown. May throw FileError.
  virtual std::optional<Pose3d> PoseAt(size_t index) = 0;
  const SequenceScan& scan() const { return scan_; }

 private:
  Frame ReadFrame(size_t index);

  SequenceScan scan_;
  size_t next_ = 0;
};

// The three layouts. Each returns a source whose info() describes the dataset.
std::unique_ptr<SequenceSource> OpenKittiRaw(const std::filesystem::path& path,
                                             const FrameSourceOptions& options);
std::unique_ptr<SequenceSource> OpenKittiOdometry(const std::filesystem::path& path,
                                                  const FrameSourceOptions& options);
std::unique_ptr<SequenceSource> OpenKittiStereo2015(const std::filesystem::path& path,
                                                    const FrameSourceOptions& options);

// Locates the drive folder of a raw dataset given the drive, date or root folder; nullopt when `path`
// holds no raw drive. Throws FileError(path) when it holds several.
std::optional<std::filesystem::path> FindRawDrive(const std::filesystem::path& path);

}  // namespace semap::io::kitti_internal
