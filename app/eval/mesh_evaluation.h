// Evaluates a mesh against a sequence's ground truth, the way the paper measures accuracy: per camera, the
// mesh's rendered depth against the Velodyne points projected into the image (engine/eval/depth_accuracy.h
// defines the filters), and, for generated sequences, against their exact depth maps.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/mesh.h"
#include "engine/eval/depth_accuracy.h"
#include "engine/eval/depth_render.h"
#include "engine/eval/error_breakdown.h"
#include "engine/eval/error_image.h"
#include "engine/eval/surface_metrics.h"
#include "engine/semantics/segmenter.h"
#include "io/frame_source.h"

namespace semap::app {

// One frame's figures (the same filters, that frame's pixels only).
struct FrameAccuracy {
  std::int64_t frame_id = 0;
  std::optional<DepthAccuracy> lidar;        // when the frame has a Velodyne scan
  std::optional<DepthAccuracy> exact_depth;  // when it has an exact depth map
};

// What EvaluateMesh does besides the totals: the error breakdown's bins and the per-pixel error images.
struct MeshEvaluationOptions {
  // Per-pixel error images (engine/eval/error_image.h) of this many frames, spread evenly over the selected
  // frames' ids (first and last included); 0 = none, unless error_image_frames names frames.
  int error_images = 0;
  // Frames (ids as on disk) to draw error images of; when non-empty it replaces error_images.
  std::vector<std::int64_t> error_image_frames;
  ErrorBreakdownOptions breakdown;
  // The colour scale and legend of the images; the point size is chosen per reference (Velodyne points
  // drawn as squares of radius point_radius_px, exact depth maps one pixel each).
  ErrorImageOptions image;
  // Labels the frames that have no label images (e.g. ENet with semantics.source: enet), for the static
  // scene and the by-class breakdown; not owned, may be null (then such frames use the mesh's labels, and
  // have no static-scene figures).
  Segmenter* segmenter = nullptr;
  void Check() const;
};

// One frame's per-pixel error picture.
struct FrameErrorImage {
  std::int64_t frame_id = 0;
  std::string reference;  // "lidar" or "exact_depth"
  cv::Mat image;          // CV_8UC3 BGR, with its legend
};

struct MeshEvaluation {
  std::int64_t frames = 0;  // frames with a pose that were evaluated
  std::int64_t frames_with_lidar = 0;
  std::int64_t frames_with_exact_depth = 0;
  std::int64_t frames_unreadable = 0;        // skipped: a file of the frame (e.g. its Velodyne scan) failed
  std::string first_unreadable;              // the first such error, naming the file
  DepthAccuracy lidar;                       // against Velodyne (the paper's RMSE)
  std::optional<DepthAccuracy> exact_depth;  // against exact depth maps (generated sequences only)
  std::uint64_t off_bytes = 0;               // mesh size as ASCII OFF (the paper's measure)
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::vector<FrameAccuracy> per_frame;  // every evaluated frame, in order
  // The two protocols (engine/eval/depth_accuracy.h): `lidar` / `exact_depth` above use the configured
  // options (strict: every error by default); these use the paper's filters (≤ 15 m, |error| ≤ 2 m).
  DepthAccuracyOptions strict_options;
  DepthAccuracyOptions paper_options;
  DepthAccuracy lidar_paper;
  std::optional<DepthAccuracy> exact_depth_paper;
  // The static scene: the strict protocol without the pixels of movable classes (MovableClassIds) by each
  // frame's own labels (label images, input.labels_dir, or MeshEvaluationOptions::segmenter's). Only the
  // frames with labels count; unset when none had them (the mesh's labels cannot tell a car that drove on:
  // they show the road behind it).
  std::int64_t frames_with_labels = 0;
  std::optional<DepthAccuracy> lidar_static;
  std::optional<DepthAccuracy> exact_depth_static;
  // Where the errors come from (strict protocol, all frames): by class, reference distance, triangle area.
  std::optional<ErrorBreakdown> lidar_breakdown;
  std::optional<ErrorBreakdown> exact_depth_breakdown;
  // Where the pixels' classes came from: "label images", "segmenter labels", "mesh labels", two or three of
  // them joined by " and ", or "none".
  std::string class_source = "none";
  std::vector<FrameErrorImage> error_images;  // as MeshEvaluationOptions asked, in frame order
  // Generated sequences with scene_mesh.ply: accuracy (by area, and per vertex) / completeness in the MVS
  // sense at accuracy.surface_threshold_m, the truth samples being the exact depth maps' points.
  std::optional<SurfaceMetrics> scene;
  double scene_threshold_m = 0.0;
  std::filesystem::path scene_mesh_path;  // the scene mesh compared with (empty when none)
  // The evaluated frames' left cameras in the world frame: their centres in order, and their mean up
  // direction (−y of the camera, unit; zero when no frame had a pose). Pictures from above use them.
  std::vector<Eigen::Vector3d> camera_centers;
  Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
};

// What labels the frames that have no label images in an evaluation (MeshEvaluationOptions::segmenter): ENet
// when `semantics.source` is enet (as the run labelled them), else none.
std::unique_ptr<Segmenter> EvaluationSegmenter(const SemanticsOptions& semantics);

// The exact depth map of frame `id` of a generated data set, if any: depth/data/%010d.png beside image_02
// (KITTI raw), depth/<stem of view id's image>.png beside images/ (Strecha layout).
std::optional<std::filesystem::path> ExactDepthPath(const io::SequenceInfo& info, std::int64_t id);

// Reads the frames of `dataset` selected by `input` (Velodyne is loaded whatever input.load_velodyne says;
// frames without a pose are skipped) and compares `mesh` with them. Throws FileError for an unreadable
// dataset; frames that fail to read are skipped and counted.
// `options` adds the breakdown's bins and the error images (throws InvalidOption on bad options).
MeshEvaluation EvaluateMesh(const Mesh& mesh, const std::filesystem::path& dataset,
                            io::FrameSourceOptions input, const DepthAccuracyOptions& accuracy = {},
                            const MeshEvaluationOptions& options = {});

}  // namespace semap::app
