#include "app/eval/mesh_evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "app/eval/mesh_evaluation_steps.h"
#include "engine/core/check.h"
#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"
#include "io/sfm/strecha.h"

namespace semap::app {

using namespace io;  // the frame sources, mesh files and ground truth of io/
namespace {

std::string ErrorImageTitle(std::int64_t frame_id, const char* reference) {
  char text[96];
  std::snprintf(text, sizeof(text), "frame %lld, mesh vs %s", static_cast<long long>(frame_id), reference);
  return text;
}

}  // namespace

std::unique_ptr<Segmenter> EvaluationSegmenter(const SemanticsOptions& semantics) {
  if (semantics.source != LabelSource::kEnet) return nullptr;
  return MakeSegmenter(semantics);
}

std::optional<std::filesystem::path> ExactDepthPath(const io::SequenceInfo& info, std::int64_t id) {
  if (info.layout == io::DatasetLayout::kStrecha) {
    const std::vector<std::filesystem::path> images = io::StrechaImageFiles(info.root);
    if (id < 0 || id >= static_cast<std::int64_t>(images.size())) return std::nullopt;
    const auto path = info.root / "depth" / (images[static_cast<std::size_t>(id)].stem().string() + ".png");
    if (std::filesystem::is_regular_file(path)) return path;
    return std::nullopt;
  }
  char name[32];
  std::snprintf(name, sizeof(name), "%010lld.png", static_cast<long long>(id));
  const auto path = info.root / "depth" / "data" / name;
  if (std::filesystem::is_regular_file(path)) return path;
  return std::nullopt;
}

void MeshEvaluationOptions::Check() const {
  SEMAP_CHECK_OPTION(error_images >= 0, "error_images", error_images, "must be >= 0");
  breakdown.Check();
  image.Check();
}

std::set<std::int64_t> ErrorImageFrames(const MeshEvaluationOptions& options, const SequenceInfo& info) {
  if (!options.error_image_frames.empty()) {
    return {options.error_image_frames.begin(), options.error_image_frames.end()};
  }
  std::set<std::int64_t> ids;
  const std::int64_t first = info.first_frame_id, span = info.last_frame_id - info.first_frame_id;
  for (int k = 0; k < options.error_images; ++k) {
    const double at = options.error_images == 1 ? 0.5 : static_cast<double>(k) / (options.error_images - 1);
    ids.insert(first + static_cast<std::int64_t>(std::lround(at * static_cast<double>(span))));
  }
  return ids;
}

std::string ClassSourceText(bool from_images, bool from_segmenter, bool from_mesh) {
  std::vector<std::string> sources;
  if (from_images) sources.push_back("label images");
  if (from_segmenter) sources.push_back("segmenter labels");
  if (from_mesh) sources.push_back("mesh labels");
  std::string text = "none";
  for (std::size_t k = 0; k < sources.size(); ++k) text = k == 0 ? sources[k] : text + " and " + sources[k];
  return text;
}

void SampleExactDepth(const cv::Mat& exact_depth, const StereoCalibration& calibration,
                      const Pose3d& world_from_cam, const DepthAccuracyOptions& accuracy,
                      std::vector<Eigen::Vector3d>* points, std::vector<double>* depths_m) {
  const int stride = accuracy.surface_pixel_stride;
  for (int v = stride / 2; v < exact_depth.rows; v += stride) {
    for (int u = stride / 2; u < exact_depth.cols; u += stride) {
      const float z = exact_depth.at<float>(v, u);
      if (z < accuracy.min_depth_m || z > accuracy.max_depth_m) continue;
      points->push_back(world_from_cam * calibration.Unproject(u, v, z));
      depths_m->push_back(z);
    }
  }
}

MeshEvaluator::MeshEvaluator(const Mesh& mesh, const SequenceInfo& info, std::vector<int> movable,
                             const DepthAccuracyOptions& accuracy, const MeshEvaluationOptions& options)
    : mesh_(mesh),
      info_(info),
      movable_(std::move(movable)),
      accuracy_(accuracy),
      triangle_areas_(TriangleAreas(mesh)),
      triangle_labels_(TriangleLabels(mesh)),
      image_frames_(ErrorImageFrames(options, info)),
      segmenter_(options.segmenter),
      sparse_image_(options.image),
      dense_image_(options.image),
      lidar_(accuracy, PaperProtocol(accuracy), options.breakdown),
      exact_(accuracy, PaperProtocol(accuracy), options.breakdown) {
  dense_image_.point_radius_px = 0;
  result_.off_bytes = OffSizeBytes(mesh);
  result_.vertices = mesh.num_vertices();
  result_.triangles = mesh.num_triangles();
  result_.strict_options = accuracy;
  result_.paper_options = PaperProtocol(accuracy);
}

void MeshEvaluator::AddUnreadable(const std::string& what) {
  if (result_.frames_unreadable++ == 0) result_.first_unreadable = what;
}

MeshEvaluator::FrameView MeshEvaluator::ViewFrame(Frame& frame) {
  FrameView view{frame, RenderDepthAndTriangles(mesh_, frame.calibration, *frame.world_from_cam), {}};
  const bool segmented = segmenter_ != nullptr && frame.labels.empty();
  if (segmented) frame.labels = segmenter_->Segment(frame.left);
  view.has_labels = !frame.labels.empty() && frame.labels.size() == view.rendered.depth.size() &&
                    frame.labels.type() == CV_8U;
  if (view.has_labels) {
    ++result_.frames_with_labels;
    (segmented ? classes_from_segmenter_ : classes_from_images_) = true;
  } else if (!triangle_labels_.empty()) {
    classes_from_mesh_ = true;
  }
  view.classes = PixelClasses(frame.labels, view.rendered.triangle, triangle_labels_);
  view.draw = image_frames_.count(frame.id) > 0;
  return view;
}

DepthAccuracy MeshEvaluator::AddReference(const FrameView& view, const cv::Mat& reference, const char* name,
                                          const char* title, const ErrorImageOptions& image,
                                          ReferenceTotals* totals) {
  const cv::Mat& mesh_depth = view.rendered.depth;
  DepthAccuracyAccumulator one(accuracy_);
  one.Add(reference, mesh_depth);
  totals->paper.Add(reference, mesh_depth);
  totals->breakdown.Add(reference, mesh_depth, view.rendered.triangle, triangle_areas_, view.classes);
  if (view.draw) {
    const Frame& frame = view.frame;
    result_.error_images.push_back({frame.id, name,
                                    RenderErrorImage(reference, mesh_depth, frame.left, accuracy_, image,
                                                     ErrorImageTitle(frame.id, title))});
  }
  totals->strict.Merge(one);
  if (view.has_labels) {
    totals->without_movable.Add(WithoutMovable(reference, view.frame.labels, movable_), mesh_depth);
    ++totals->frames_without_movable;
  }
  return one.Result();
}

void MeshEvaluator::AddFrame(Frame& frame) {
  ++result_.frames;
  result_.camera_centers.push_back(frame.world_from_cam->translation());
  result_.camera_up -= frame.world_from_cam->linear().col(1);
  const FrameView view = ViewFrame(frame);
  FrameAccuracy frame_accuracy;
  frame_accuracy.frame_id = frame.id;
  if (frame.velodyne) {
    const cv::Mat lidar_depth = LidarDepthImage(*frame.velodyne, frame.calibration, accuracy_);
    frame_accuracy.lidar = AddReference(view, lidar_depth, "lidar", "Velodyne", sparse_image_, &lidar_);
    ++result_.frames_with_lidar;
  }
  if (const auto path = ExactDepthPath(info_, frame.id)) {
    const cv::Mat exact_depth = ReadDepthPngMm(*path);
    frame_accuracy.exact_depth =
        AddReference(view, exact_depth, "exact_depth", "exact depth", dense_image_, &exact_);
    SampleExactDepth(exact_depth, frame.calibration, *frame.world_from_cam, accuracy_, &truth_samples_,
                     &truth_sample_depths_m_);
    ++result_.frames_with_exact_depth;
  }
  result_.per_frame.push_back(frame_accuracy);
}

void MeshEvaluator::CompareWithSceneMesh() {
  const auto scene_mesh = info_.root / "scene_mesh.ply";
  if (result_.frames_with_exact_depth == 0 || !std::filesystem::is_regular_file(scene_mesh)) return;
  SurfaceMetricsOptions surface;
  surface.threshold_m = accuracy_.surface_threshold_m;
  surface.area_samples = accuracy_.surface_area_samples;
  result_.scene =
      CompareSurfaces(mesh_, ReadMeshPly(scene_mesh), truth_samples_, surface, truth_sample_depths_m_);
  result_.scene_threshold_m = surface.threshold_m;
  result_.scene_mesh_path = scene_mesh;
}

MeshEvaluation MeshEvaluator::Finish(const ClassMap& class_map) {
  if (result_.camera_up.norm() > 0.0) result_.camera_up.normalize();
  result_.lidar = lidar_.strict.Result();
  result_.lidar_paper = lidar_.paper.Result();
  if (result_.frames_with_lidar > 0) result_.lidar_breakdown = lidar_.breakdown.Result(class_map);
  if (result_.frames_with_exact_depth > 0) {
    result_.exact_depth = exact_.strict.Result();
    result_.exact_depth_paper = exact_.paper.Result();
    result_.exact_depth_breakdown = exact_.breakdown.Result(class_map);
  }
  if (lidar_.frames_without_movable > 0) result_.lidar_static = lidar_.without_movable.Result();
  if (exact_.frames_without_movable > 0) result_.exact_depth_static = exact_.without_movable.Result();
  result_.class_source = ClassSourceText(classes_from_images_, classes_from_segmenter_, classes_from_mesh_);
  CompareWithSceneMesh();
  return std::move(result_);
}

MeshEvaluation EvaluateMesh(const Mesh& mesh, const std::filesystem::path& dataset, FrameSourceOptions input,
                            const DepthAccuracyOptions& accuracy, const MeshEvaluationOptions& options) {
  options.Check();
  input.load_velodyne = true;
  const SequenceInfo info = DescribeDataset(dataset, input);
  auto source = OpenFrameSource(dataset, input);
  MeshEvaluator evaluator(mesh, info, MovableClassIds(source->class_map()), accuracy, options);
  while (true) {
    std::optional<Frame> frame;
    try {
      frame = source->Next();
    } catch (const FrameError& e) {
      evaluator.AddUnreadable(e.what());
      continue;  // an unreadable frame is not evaluated
    }
    if (!frame) break;
    if (frame->world_from_cam) evaluator.AddFrame(*frame);
  }
  return evaluator.Finish(source->class_map());
}

}  // namespace semap::app
