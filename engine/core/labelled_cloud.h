// A labelled point cloud in the world frame, stored as parallel arrays (structure of arrays).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/depth_view.h"

namespace semap {

// Per-point attributes; `positions_world` defines size(). Each other per-point array is either empty
// (attribute absent) or of size(). Every point refers to the camera that first observed it through
// `camera_index` into `camera_centers_world` (the paper's labelling rule: the first camera that saw it).
struct LabelledCloud {
  std::vector<Eigen::Vector3d> positions_world;
  std::vector<std::array<std::uint8_t, 3>> colors_rgb;  // optional
  std::vector<Label> labels;                            // optional (absent = all unlabelled)
  std::vector<Eigen::Vector2f> pixels_px;               // optional: (u, v) in the first observing image
  std::vector<float> confidence;                        // optional: disparity confidence in [0, 1]
  std::vector<std::uint32_t> camera_index;              // required when cameras are present

  // Cameras (one per observing frame).
  std::vector<Eigen::Vector3d> camera_centers_world;
  std::vector<std::int64_t> camera_frame_ids;
  // Optional, per camera: its depth map, for the map's visibility votes (every valid pixel votes, not only
  // the points kept here). Shared, never modified.
  std::vector<std::shared_ptr<const DepthView>> camera_views;

  size_t size() const { return positions_world.size(); }
  bool empty() const { return positions_world.empty(); }

  // Checks the array sizes and camera indices (programmer error if violated: asserts).
  void AssertConsistent() const;

  // The points at `indices` (in that order), every attribute carried; cameras are copied unchanged.
  LabelledCloud Subset(const std::vector<std::uint32_t>& indices) const;

  // Appends `other`'s points and cameras (camera indices are offset).
  void Append(const LabelledCloud& other);
};

}  // namespace semap
