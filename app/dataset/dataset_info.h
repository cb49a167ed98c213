// `semap info`: what a dataset folder holds, as the frame sources will read it.
#pragma once

#include <string>

#include "app/config/config.h"

namespace semap::app {

// Prints the dataset's layout, frames, image size, calibration, what it holds (poses, timestamps, Velodyne,
// labels) and, when it has label images, the class composition over `sample_frames` of them (0 = all; an
// unreadable one is skipped with a warning). Throws io::FileError naming the path when it is no dataset.
void PrintDatasetInfo(const Config& config, const std::string& path, int sample_frames);

}  // namespace semap::app
