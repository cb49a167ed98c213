// The one interface through which frames enter semap, whatever the on-disk layout.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "engine/core/class_map.h"
#include "engine/core/frame.h"

namespace semap::io {

enum class DatasetLayout { kAuto, kKittiRaw, kKittiOdometry, kKittiStereo2015 };

const char* DatasetLayoutName(DatasetLayout layout);

struct FrameSourceOptions {
  // Layout of the dataset folder; auto detects it from the folder's contents.
  DatasetLayout layout = DatasetLayout::kAuto;
  // First frame index to read (0-based, as numbered on disk).
  int first_frame = 0;
  // Number of frames to read; 0 = until the end of the sequence.
  int max_frames = 0;
  // Read the Velodyne scans when present (needed for evaluation only).
  bool load_velodyne = true;
  // Folder of label PNGs (one per frame, same stem); empty = the layout's own (e.g. semantic/data of a
  // generated sequence) when present, else none.
  std::string labels_dir;
  // YAML class map naming the id scheme of the label images; empty = Cityscapes 20 classes.
  std::string class_map;

  void Check() const;
};

// A lazily read sequence of frames. Not thread-safe: one consumer calls Next().
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual DatasetLayout layout() const = 0;
  // Total number of frames this source will yield (after first_frame / max_frames).
  virtual std::int64_t size() const = 0;
  // The next frame, or std::nullopt at the end. A frame that cannot be read throws FrameError (the
  // caller logs, counts and goes on with the next one).
  virtual std::optional<Frame> Next() = 0;
  virtual const ClassMap& class_map() const = 0;
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

}  // namespace semap::io
