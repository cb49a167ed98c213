// The one interface through which frames enter semap, whatever the on-disk layout.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/frame.h"
#include "engine/core/options.h"
#include "engine/pipeline/stages.h"
#include "io/file_error.h"

namespace semap::io {

// kStrecha: a calibrated multi-view set without a stereo pair (io/sfm/strecha.h): depth by plane sweep.
enum class DatasetLayout { kAuto, kKittiRaw, kKittiOdometry, kKittiStereo2015, kStrecha };

const char* DatasetLayoutName(DatasetLayout layout);

// Which stereo pair of a KITTI odometry sequence is read.
enum class CameraPair { kAuto, kGray, kColor };

struct FrameSourceOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  DatasetLayout layout = DatasetLayout::kAuto;
  int first_frame = 0;
  int max_frames = 0;
  bool load_velodyne = true;
  // Read the label images (not a config key: a run sets it from semantics.source, so that with `none` or
  // `enet` a missing or damaged label image does not cost the frame).
  bool load_labels = true;
  std::string labels_dir;
  std::string class_map;
  CameraPair odometry_pair = CameraPair::kAuto;
  double default_frame_period_s = 0.1;
  int loops = 1;
  double loop_gap_m = 100.0;
  int neighbour_views = 4;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Enum("layout", &layout,
           {{"auto", DatasetLayout::kAuto},
            {"kitti_raw", DatasetLayout::kKittiRaw},
            {"kitti_odometry", DatasetLayout::kKittiOdometry},
            {"kitti_stereo2015", DatasetLayout::kKittiStereo2015},
            {"strecha", DatasetLayout::kStrecha}},
           "dataset layout; auto detects it from the folder's contents");
    v.Field("first_frame", &first_frame, "first frame index to read (0-based, as numbered on disk)",
            AtLeast(0));
    v.Field("max_frames", &max_frames, "number of frames to read; 0 = to the end of the sequence",
            AtLeast(0));
    v.Field("load_velodyne", &load_velodyne,
            "read the Velodyne scans when present (needed for evaluation only)");
    v.Field("labels_dir", &labels_dir,
            "folder of label PNGs, one per frame with the image's stem; empty = the layout's own (e.g. "
            "semantic/data of a generated sequence) if any");
    v.Field("class_map", &class_map,
            "YAML class map naming the id scheme of the label images; empty = Cityscapes 20 classes");
    v.Enum(
        "odometry_pair", &odometry_pair,
        {{"auto", CameraPair::kAuto}, {"gray", CameraPair::kGray}, {"color", CameraPair::kColor}},
        "KITTI odometry: stereo pair to read (gray image_0/1, colour image_2/3; auto = colour if present)");
    v.Field("default_frame_period_s", &default_frame_period_s,
            "frame period for timestamps when the dataset has none, s (KITTI records at 10 Hz)", Above(0));
    // The map meets new ground on every pass (see OpenFrameSource).
    v.Field("loops", &loops,
            "read the frames this many times in a row (soak runs); pass k is shifted k times along the "
            "longest axis of the first pass's track, its ids and timestamps following on",
            AtLeast(1));
    // Above 2 × depth.max_depth_m, what one pass sees does not overlap the next.
    v.Field("loop_gap_m", &loop_gap_m,
            "gap between the camera tracks of consecutive passes, m (keep above 2 x depth.max_depth_m)",
            AtLeast(0));
    v.Field("neighbour_views", &neighbour_views,
            "multi-view sets (strecha layout): each frame's depth is swept against this many of the set's "
            "views, the nearest cameras looking the same way (more: fewer occlusions and ambiguities, cost "
            "grows with it)",
            AtLeast(1));
  }

  void Check() const { CheckDeclaredRanges(*this); }
};

// What a dataset folder holds, as `semap info` reports it (nothing but the first image's header is read).
struct SequenceInfo {
  DatasetLayout layout = DatasetLayout::kAuto;
  std::filesystem::path root;           // the drive / sequence / subset folder the frames come from
  std::filesystem::path left_dir;       // folder of the left images
  std::int64_t num_frames = 0;          // frames selected by first_frame / max_frames
  std::int64_t num_frames_on_disk = 0;  // left images in the folder
  std::int64_t first_frame_id = 0;      // ids (as on disk) of the first and last selected frames
  std::int64_t last_frame_id = 0;
  bool color = false;             // colour (BGR) or gray images
  StereoCalibration calibration;  // image size from the first selected left image
  bool has_poses = false;
  bool has_timestamps = false;  // false: timestamps are id × default_frame_period_s
  bool has_velodyne = false;    // scans and their calibration present
  std::optional<Pose3d> cam_from_velo;
  bool has_labels = false;
  std::filesystem::path labels_dir;
  std::vector<std::filesystem::path> label_files;  // the selected frames' label images that exist
  ClassMap class_map;
  std::vector<std::string> notes;  // why something present on disk is not used
};

// A lazily read sequence of frames. Not thread-safe: one consumer calls Next().
// It is the pipeline's FrameReader: `semap run` hands it to the Pipeline as is.
class FrameSource : public FrameReader {
 public:
  ~FrameSource() override = default;
  virtual DatasetLayout layout() const = 0;
  // Total number of frames this source will yield (after first_frame / max_frames).
  virtual std::int64_t size() const = 0;
  // The next frame, or std::nullopt at the end. A frame that cannot be read throws FrameError (the
  // caller logs, counts and goes on with the next one).
  std::optional<Frame> Next() override = 0;
  virtual const ClassMap& class_map() const = 0;
  // What the source reads, as `semap info` reports it (of one pass, with input.loops > 1).
  virtual const SequenceInfo& info() const = 0;
};

// A frame that could not be read: names the file and the problem. The source stays usable.
class FrameError : public std::runtime_error {
 public:
  FrameError(std::int64_t frame_id, const std::string& message)
      : std::runtime_error(message), frame_id_(frame_id) {}
  std::int64_t frame_id() const { return frame_id_; }

 private:
  std::int64_t frame_id_;
};

// The layout of the dataset at `path` (raw drive / date folder, odometry root or sequence folder, stereo-2015
// folder). Throws FileError naming the path when it is missing or matches no layout.
DatasetLayout DetectLayout(const std::filesystem::path& path);

// Opens the dataset at `path` for streaming (layout from options, or detected). Throws FileError (naming
// the file and the problem) or InvalidOption when the dataset cannot be used at all: missing folder,
// missing or bad calibration, poses or timestamps file shorter than the frames, bad class map.
// With options.loops > 1 the selected frames are read loops times: frame i of pass k has id
// i + k·(last id - first id + 1), its pose translated by k·shift (shift: the first pass's track extent along
// its longest axis + loop_gap_m) and its timestamp offset so that the jump between passes is driven at the
// first pass's mean speed (a pose-jump check sees an ordinary drive).
std::unique_ptr<FrameSource> OpenFrameSource(const std::filesystem::path& path,
                                             const FrameSourceOptions& options);

// Describes the dataset as OpenFrameSource would read it (same errors).
SequenceInfo DescribeDataset(const std::filesystem::path& path, const FrameSourceOptions& options);

}  // namespace semap::io
