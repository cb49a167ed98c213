// The steps of EvaluateMesh (app/eval/mesh_evaluation.h), each on its own: which frames get error images,
// one frame against its references, the exact depth maps' samples of the true surface, and the totals.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "app/eval/mesh_evaluation.h"

namespace semap::app {

// The frame ids to draw error images of: the named ones, else `error_images` spread evenly over the
// selection's ids (first and last included; one: the middle).
std::set<std::int64_t> ErrorImageFrames(const MeshEvaluationOptions& options, const io::SequenceInfo& info);

// "label images", "segmenter labels" and "mesh labels", those that are true, joined by " and "; "none" when
// none is.
std::string ClassSourceText(bool from_images, bool from_segmenter, bool from_mesh);

// The true surface as an exact depth map samples it: every `accuracy.surface_pixel_stride`-th pixel in both
// directions (from half a stride in) whose depth is within [min_depth_m, max_depth_m], unprojected with the
// calibration and moved into the world by `world_from_cam`; appended to `points`, and its depth to
// `depths_m`.
void SampleExactDepth(const cv::Mat& exact_depth, const StereoCalibration& calibration,
                      const Pose3d& world_from_cam, const DepthAccuracyOptions& accuracy,
                      std::vector<Eigen::Vector3d>* points, std::vector<double>* depths_m);

// One reference (Velodyne or exact depth) summed over the frames, under both protocols, with its breakdown.
struct ReferenceTotals {
  ReferenceTotals(const DepthAccuracyOptions& strict, const DepthAccuracyOptions& paper,
                  const ErrorBreakdownOptions& breakdown_options)
      : strict(strict), paper(paper), breakdown(strict, breakdown_options), without_movable(strict) {}
  DepthAccuracyAccumulator strict;
  DepthAccuracyAccumulator paper;
  ErrorBreakdownAccumulator breakdown;
  DepthAccuracyAccumulator without_movable;  // the static scene: frames with labels only
  std::int64_t frames_without_movable = 0;
};

// A mesh evaluated against the frames of a sequence, one frame after the other.
class MeshEvaluator {
 public:
  // `mesh`, `info`, `accuracy` and `options` must outlive the evaluator; `movable` are the class map's
  // movable classes (MovableClassIds).
  MeshEvaluator(const Mesh& mesh, const io::SequenceInfo& info, std::vector<int> movable,
                const DepthAccuracyOptions& accuracy, const MeshEvaluationOptions& options);

  // A frame that could not be read: counted, its error kept when it is the first.
  void AddUnreadable(const std::string& what);
  // A frame with a pose: the mesh rendered into it against its Velodyne scan and exact depth map (labelled by
  // the options' segmenter first when it has no labels).
  void AddFrame(Frame& frame);
  // The totals (the breakdowns' classes named by `class_map`) and the comparison with the sequence's scene
  // mesh, when it has one and exact depth maps.
  MeshEvaluation Finish(const ClassMap& class_map);

 private:
  // What one frame gives each reference: the mesh's depth and triangles in it, its pixels' classes, its
  // labels (empty: none usable).
  struct FrameView {
    const Frame& frame;
    DepthAndTriangles rendered;
    cv::Mat classes;
    bool has_labels = false;
    bool draw = false;  // an error image of this frame is asked for
  };
  FrameView ViewFrame(Frame& frame);
  // One reference depth map of the frame into its totals and (when asked) an error image; returns the
  // frame's strict figures.
  DepthAccuracy AddReference(const FrameView& view, const cv::Mat& reference, const char* name,
                             const char* title, const ErrorImageOptions& image, ReferenceTotals* totals);
  void CompareWithSceneMesh();

  const Mesh& mesh_;
  const io::SequenceInfo& info_;
  const std::vector<int> movable_;
  const DepthAccuracyOptions& accuracy_;
  const std::vector<double> triangle_areas_;
  const std::vector<int> triangle_labels_;
  const std::set<std::int64_t> image_frames_;
  Segmenter* const segmenter_;
  ErrorImageOptions sparse_image_, dense_image_;
  ReferenceTotals lidar_, exact_;
  bool classes_from_images_ = false, classes_from_segmenter_ = false, classes_from_mesh_ = false;
  std::vector<Eigen::Vector3d> truth_samples_;  // the exact depth maps' points, in the world frame
  std::vector<double> truth_sample_depths_m_;   // and the depth each was seen at
  MeshEvaluation result_;
};

}  // namespace semap::app
