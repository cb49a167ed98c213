// A structure-from-motion / SLAM reconstruction: posed views, 3D points and which view observed which point.
// One struct for every input format (COLMAP, OpenMVG sfm_data.json, the 2018 manifold mapper's SLAM JSON);
// the readers and writers are in colmap.h, openmvg.h and slam_json.h.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/class_map.h"

namespace semap::io {

enum class SfmFormat {
  kColmap,    // COLMAP model folder: cameras / images / points3D as .txt or .bin
  kOpenMvg,   // OpenMVG sfm_data.json
  kSlamJson,  // the ORB-SLAM-style JSON of the 2018 manifold mapper (slam_data_version 0.2 / 0.3)
};

// "colmap", "openmvg", "slam-json" (the names of `semap map-sfm --format`).
const char* SfmFormatName(SfmFormat format);
// Parses one of the names above; throws std::invalid_argument listing them.
SfmFormat SfmFormatFromName(const std::string& name);

// A camera model with its parameters, in the source format's naming and parameter order: COLMAP models
// ("SIMPLE_PINHOLE": f cx cy; "PINHOLE": fx fy cx cy; "SIMPLE_RADIAL": f cx cy k; ...) or OpenMVG /
// SLAM JSON models ("pinhole": f cx cy; "pinhole_radial_k1": f cx cy k1; "pinhole_radial_k3": f cx cy k1 k2
// k3; ...). The writers translate the models that have an exact equivalent (see colmap.h, openmvg.h).
struct SfmIntrinsics {
  std::int64_t id = 0;  // the file's id (COLMAP CAMERA_ID, OpenMVG / SLAM JSON intrinsic key)
  std::string model;
  int width_px = 0;
  int height_px = 0;
  std::vector<double> params;
};

inline constexpr std::int64_t kNoIntrinsics = -1;

// A posed image. The camera frame is the formats' common one: x right, y down, z forward (optical axis).
struct SfmView {
  std::int64_t id = 0;                         // the file's id (COLMAP IMAGE_ID, OpenMVG view key, viewId)
  std::string name;                            // image file, relative to SfmReconstruction::image_root
  std::int64_t intrinsics_id = kNoIntrinsics;  // an SfmIntrinsics::id, or kNoIntrinsics
  Pose3d world_from_cam = Pose3d::Identity();

  Eigen::Vector3d center_world() const { return world_from_cam.translation(); }
};

// View `view` observed point `point` (indices into SfmReconstruction::views / points_world) at `pixel_px`
// (NaN when the format gives no image position).
struct SfmObservation {
  std::uint32_t point = 0;
  std::uint32_t view = 0;
  Eigen::Vector2d pixel_px{std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::quiet_NaN()};
};

// Views keep the file's order: it is the keyframe order of `semap map-sfm --incremental`. Points are
// structure of arrays; colours and labels are either empty (absent) or one per point. Observations are in
// canonical order: by point, then by view (SortObservations).
struct SfmReconstruction {
  std::string image_root;  // folder of the images when the format names one (informational)
  std::vector<SfmIntrinsics> intrinsics;
  std::vector<SfmView> views;
  std::vector<std::int64_t> point_ids;  // the file's ids (COLMAP POINT3D_ID, OpenMVG key, pointId)
  std::vector<Eigen::Vector3d> points_world;
  std::vector<std::array<std::uint8_t, 3>> point_colors_rgb;  // optional
  std::vector<Label> point_labels;                            // optional
  std::vector<SfmObservation> observations;

  std::size_t num_points() const { return points_world.size(); }
  // Array sizes, observation indices and order (programmer error if violated: asserts).
  void AssertConsistent() const;
  // Sorts the observations by (point, view), keeping the order of equal pairs.
  void SortObservations();
  // The intrinsics with this id, or nullptr.
  const SfmIntrinsics* FindIntrinsics(std::int64_t id) const;
};

// Reads a reconstruction: COLMAP from its model folder (binary when cameras.bin, images.bin and points3D.bin
// are all there, else text), OpenMVG and SLAM JSON from their file. Throws FileError / ParseError naming the
// file, the entry and the field of the first problem found.
SfmReconstruction ReadSfm(const std::filesystem::path& path, SfmFormat format);

}  // namespace semap::io
