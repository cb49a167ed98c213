// Writes a generated sequence in the KITTI raw layout (plus ground-truth depth, labels and scene mesh).
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "engine/sim/synthetic_sequence.h"
#include "io/synth/oxts.h"

namespace semap::io {

// Where the files of a written sequence are.
struct SynthLayout {
  std::filesystem::path date_dir;   // ROOT/DATE: the three calib files
  std::filesystem::path drive_dir;  // ROOT/DATE/DATE_drive_NNNN_sync
};

// The date and drive number of generated sequences.
inline constexpr char kSynthDate[] = "2026_01_01";
inline constexpr int kSynthDrive = 1;

SynthLayout SynthLayoutFor(const std::filesystem::path& root);

struct SynthWriteSummary {
  SynthLayout layout;
  int num_frames = 0;
  sim::LabelHistogram label_pixels;  // over all left label images
  std::uint64_t lidar_points = 0;    // over all scans
};

// Writes every frame of `sequence` under `root` (created if missing; existing files are overwritten):
//   ROOT/DATE/calib_cam_to_cam.txt, calib_velo_to_cam.txt, calib_imu_to_velo.txt
//   ROOT/DATE/DATE_drive_0001_sync/{image_02,image_03}/data/%010d.png   (rectified BGR colour)
//     velodyne_points/data/%010d.bin  (float32 x y z reflectance, Velodyne frame)
//     oxts/data/%010d.txt             (30 values; the devkit conversion gives the true IMU trajectory)
//     semantic/data/%010d.png         (uint8 Cityscapes ids of image_02)
//     depth/data/%010d.png            (uint16 depth of image_02 in mm, camera z; 0 = none or >= 65.535 m)
//     */timestamps.txt (10 Hz), oxts/dataformat.txt,
//     scene_mesh.ply (binary, double precision, per-vertex labels, in the world frame = IMU frame of frame 0)
//     gt_world_from_cam2.txt (one 3x4 row-major pose per frame, same world frame)
// Frames are rendered and written in parallel (TBB); the output bytes do not depend on the thread count.
// `progress(done, total)` is called after each frame (from worker threads, serialised). Throws
// io::FileError naming the path when a file cannot be written.
SynthWriteSummary WriteSyntheticKittiRaw(const sim::SyntheticSequence& sequence,
                                         const std::filesystem::path& root,
                                         const std::function<void(int, int)>& progress = {});

// The calib file texts (KITTI keys; values in %.12e).
std::string FormatCalibCamToCam(const sim::SensorRig& rig);
std::string FormatCalibVeloToCam(const sim::SensorRig& rig);
std::string FormatCalibImuToVelo(const sim::SensorRig& rig);

// OXTS packets of every frame of a sequence (georeferenced by its origin_* options).
std::vector<OxtsPacket> SynthOxtsPackets(const sim::SyntheticSequence& sequence);

// "2026-01-01 12:00:00.000000000" + t_s.
std::string FormatKittiTimestamp(double t_s);

}  // namespace semap::io
