// `semap depth`: the depth stage on one frame (disparity PNGs and the labelled point cloud), or on every
// selected frame as depth maps with poses and intrinsics for other fusion tools (bench/tsdf_compare.sh).
#pragma once

#include <filesystem>
#include <string>

#include "app/config/config.h"

namespace semap::app {

struct FrameDepthRequest {
  std::string dataset;         // KITTI raw, odometry, stereo-2015 or generated
  int frame = 0;               // frame number as on disk (e.g. 57 for 000057_10.png)
  std::filesystem::path out;   // created
  bool label_colours = false;  // colour the cloud's points by label instead of by image
  bool ascii = false;          // ASCII PLY instead of binary
};

// SGBM and the labelling rule on one frame: writes disparity_NNNNNN.png (KITTI uint16), a false-colour
// disparity_colour_NNNNNN.png and cloud_NNNNNN.ply, and prints what it found. Throws naming the file or
// frame.
void WriteFrameDepth(const Config& config, const FrameDepthRequest& request);

// Every selected frame through the depth stage of `semap run` (SGBM, point filters, labels, sky removal),
// densely (no point budget): out/depth/NNNNNN.png (16-bit depth in mm, 0 = none), out/poses.txt ("id" then
// world_from_cam as 3×4 row-major, a line per frame) and out/camera.txt ("width_px height_px fx_px fy_px
// cx_px cy_px"). Throws for a frame without a pose or a file that cannot be written.
void WriteAllDepthMaps(const Config& config, const std::string& dataset, const std::filesystem::path& out);

}  // namespace semap::app
