// Reading one frame of a dataset for the single-frame commands (`semap depth`, `semap segment`).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

#include "app/config/config.h"
#include "engine/core/frame.h"
#include "io/frame_source.h"

namespace semap::app {

struct FrameAt {
  Frame frame;
  ClassMap class_map;  // id scheme of the dataset's label images
};

// The frame numbered `index` on disk (e.g. 57 for 000057_10.png) of the dataset at `path`, read with
// config.input (first_frame and max_frames are replaced). Throws io::FileError / std::runtime_error naming
// the path and index.
FrameAt ReadFrameAt(const std::filesystem::path& path, int index, io::FrameSourceOptions input);

}  // namespace semap::app
