// The commands on one cloud or one frame: `semap simplify` (a labelled point cloud through one simplification
// method) and `semap segment` (the built-in segmenter on one frame).
#pragma once

#include <filesystem>
#include <string>

#include "app/config/config.h"

namespace semap::app {

struct SimplifyCloudRequest {
  std::string cloud;   // .ply with a per-vertex `label` (class ids of config.input.class_map)
  std::string out;     // the kept points as PLY; empty = statistics only
  bool ascii = false;  // ASCII PLY instead of binary
};

// Simplifies the cloud with config.simplify and prints the points in / kept / removed per class and the time.
// Throws io::FileError naming an unreadable cloud or class map, or an unwritable output.
void SimplifyCloudFile(const Config& config, const SimplifyCloudRequest& request);

struct SegmentFrameRequest {
  std::string dataset;        // KITTI raw, odometry, stereo-2015 or generated
  int frame = 0;              // frame number as on disk (e.g. 57 for 000057_10.png)
  std::filesystem::path out;  // created
  double alpha = 0.5;         // weight of the label colours in the overlay
};

// Runs the built-in segmenter (ENet Cityscapes, whatever config.semantics.source says) on the frame: writes
// labels_NNNNNN.png (class ids) and overlay_NNNNNN.png, and prints the time and the class shares.
void SegmentFrame(const Config& config, const SegmentFrameRequest& request);

}  // namespace semap::app
