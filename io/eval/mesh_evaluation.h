// Evaluates a mesh against a sequence's ground truth, the way the paper measures accuracy: per camera, the
// mesh's rendered depth against the Velodyne points projected into the image (engine/eval/depth_accuracy.h
// defines the filters), and, for generated sequences, against their exact depth maps.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>
#include <string>

#include "engine/core/mesh.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/eval/depth_render.h"
#include "engine/eval/surface_metrics.h"
#include "io/frame_source.h"

namespace semap::io {

// One frame's figures (the same filters, that frame's pixels only).
struct FrameAccuracy {
  std::int64_t frame_id = 0;
  std::optional<DepthAccuracy> lidar;        // when the frame has a Velodyne scan
  std::optional<DepthAccuracy> exact_depth;  // when it has an exact depth map
};

struct MeshEvaluation {
  std::int64_t frames = 0;                    // frames with a pose that were evaluated
  std::int64_t frames_with_lidar = 0;
  std::int64_t frames_with_exact_depth = 0;
  std::int64_t frames_unreadable = 0;         // skipped: a file of the frame (e.g. its Velodyne scan) failed
  std::string first_unreadable;               // the first such error, naming the file
  DepthAccuracy lidar;                        // against Velodyne (the paper's RMSE)
  std::optional<DepthAccuracy> exact_depth;   // against exact depth maps (generated sequences only)
  std::uint64_t off_bytes = 0;                // mesh size as ASCII OFF (the paper's measure)
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::vector<FrameAccuracy> per_frame;       // every evaluated frame, in order
  // Generated sequences with scene_mesh.ply: accuracy (by area, and per vertex) / completeness in the MVS
  // sense at accuracy.surface_threshold_m, the truth samples being the exact depth maps' points.
  std::optional<SurfaceMetrics> scene;
  double scene_threshold_m = 0.0;
  std::filesystem::path scene_mesh_path;        // the scene mesh compared with (empty when none)
  // The evaluated frames' left cameras in the world frame: their centres in order, and their mean up
  // direction (−y of the camera, unit; zero when no frame had a pose). Pictures from above use them.
  std::vector<Eigen::Vector3d> camera_centers;
  Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
};

// Reads the frames of `dataset` selected by `input` (Velodyne is loaded whatever input.load_velodyne says;
// frames without a pose are skipped) and compares `mesh` with them. Throws FileError for an unreadable
// dataset; frames that fail to read are skipped and counted.
MeshEvaluation EvaluateMesh(const Mesh& mesh, const std::filesystem::path& dataset, FrameSourceOptions input,
                            const DepthAccuracyOptions& accuracy = {});

}  // namespace semap::io
