#include "app/eval/mesh_evaluation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "engine/core/check.h"
#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"
#include "io/sfm/strecha.h"

namespace semap::app {

using namespace io;  // the frame sources, mesh files and ground truth of io/
namespace {

// The frame ids to draw error images of: the named ones, else `count` spread evenly over the selection.
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

MeshEvaluation EvaluateMesh(const Mesh& mesh, const std::filesystem::path& dataset, FrameSourceOptions input,
                            const DepthAccuracyOptions& accuracy, const MeshEvaluationOptions& options) {
  options.Check();
  input.load_velodyne = true;
  const SequenceInfo info = DescribeDataset(dataset, input);
  auto source = OpenFrameSource(dataset, input);
  const DepthAccuracyOptions paper = PaperProtocol(accuracy);
  DepthAccuracyAccumulator lidar(accuracy), lidar_paper(paper);
  DepthAccuracyAccumulator exact(accuracy), exact_paper(paper);
  DepthAccuracyAccumulator lidar_static(accuracy), exact_static(accuracy);
  const std::vector<int> movable = MovableClassIds(source->class_map());
  std::int64_t static_lidar_frames = 0, static_exact_frames = 0;
  ErrorBreakdownAccumulator lidar_breakdown(accuracy, options.breakdown);
  ErrorBreakdownAccumulator exact_breakdown(accuracy, options.breakdown);
  const std::vector<double> triangle_areas = TriangleAreas(mesh);
  const std::vector<int> triangle_labels = TriangleLabels(mesh);
  const std::set<std::int64_t> image_frames = ErrorImageFrames(options, info);
  ErrorImageOptions sparse_image = options.image, dense_image = options.image;
  dense_image.point_radius_px = 0;
  bool classes_from_images = false, classes_from_segmenter = false, classes_from_mesh = false;
  std::vector<Eigen::Vector3d> truth_samples;  // the exact depth maps' points, in the world frame
  std::vector<double> truth_sample_depths_m;   // and the depth each was seen at
  MeshEvaluation result;
  result.off_bytes = OffSizeBytes(mesh);
  result.vertices = mesh.num_vertices();
  result.triangles = mesh.num_triangles();
  result.strict_options = accuracy;
  result.paper_options = paper;
  while (true) {
    std::optional<Frame> frame;
    try {
      frame = source->Next();
    } catch (const FrameError& e) {
      if (result.frames_unreadable++ == 0) result.first_unreadable = e.what();
      continue;  // an unreadable frame is not evaluated
    }
    if (!frame) break;
    if (!frame->world_from_cam) continue;
    ++result.frames;
    result.camera_centers.push_back(frame->world_from_cam->translation());
    result.camera_up -= frame->world_from_cam->linear().col(1);
    const DepthAndTriangles rendered =
        RenderDepthAndTriangles(mesh, frame->calibration, *frame->world_from_cam);
    const cv::Mat& mesh_depth = rendered.depth;
    const bool segmented = options.segmenter != nullptr && frame->labels.empty();
    if (segmented) frame->labels = options.segmenter->Segment(frame->left);
    const bool frame_labels =
        !frame->labels.empty() && frame->labels.size() == mesh_depth.size() && frame->labels.type() == CV_8U;
    if (frame_labels) {
      ++result.frames_with_labels;
      (segmented ? classes_from_segmenter : classes_from_images) = true;
    } else if (!triangle_labels.empty()) {
      classes_from_mesh = true;
    }
    const cv::Mat classes = PixelClasses(frame->labels, rendered.triangle, triangle_labels);
    const bool draw = image_frames.count(frame->id) > 0;
    FrameAccuracy frame_accuracy;
    frame_accuracy.frame_id = frame->id;
    // One reference depth map of this frame into the strict and paper figures, the breakdown and (for the
    // chosen frames) an error image; returns the frame's strict figures.
    const auto add_reference = [&](const cv::Mat& reference, const char* name, const char* title,
                                   const ErrorImageOptions& image, DepthAccuracyAccumulator* total,
                                   DepthAccuracyAccumulator* total_paper,
                                   ErrorBreakdownAccumulator* breakdown) {
      DepthAccuracyAccumulator one(accuracy);
      one.Add(reference, mesh_depth);
      total_paper->Add(reference, mesh_depth);
      breakdown->Add(reference, mesh_depth, rendered.triangle, triangle_areas, classes);
      if (draw) {
        result.error_images.push_back({frame->id, name,
                                       RenderErrorImage(reference, mesh_depth, frame->left, accuracy, image,
                                                        ErrorImageTitle(frame->id, title))});
      }
      total->Merge(one);
      return one.Result();
    };
    if (frame->velodyne) {
      const cv::Mat lidar_depth = LidarDepthImage(*frame->velodyne, frame->calibration, accuracy);
      frame_accuracy.lidar = add_reference(lidar_depth, "lidar", "Velodyne", sparse_image, &lidar,
                                           &lidar_paper, &lidar_breakdown);
      if (frame_labels) {
        lidar_static.Add(WithoutMovable(lidar_depth, frame->labels, movable), mesh_depth);
        ++static_lidar_frames;
      }
      ++result.frames_with_lidar;
    }
    if (const auto path = ExactDepthPath(info, frame->id)) {
      const cv::Mat exact_depth = ReadDepthPngMm(*path);
      frame_accuracy.exact_depth = add_reference(exact_depth, "exact_depth", "exact depth", dense_image,
                                                 &exact, &exact_paper, &exact_breakdown);
      if (frame_labels) {
        exact_static.Add(WithoutMovable(exact_depth, frame->labels, movable), mesh_depth);
        ++static_exact_frames;
      }
      const int stride = accuracy.surface_pixel_stride;
      for (int v = stride / 2; v < exact_depth.rows; v += stride) {
        for (int u = stride / 2; u < exact_depth.cols; u += stride) {
          const float z = exact_depth.at<float>(v, u);
          if (z < accuracy.min_depth_m || z > accuracy.max_depth_m) continue;
          truth_samples.push_back(*frame->world_from_cam * frame->calibration.Unproject(u, v, z));
          truth_sample_depths_m.push_back(z);
        }
      }
      ++result.frames_with_exact_depth;
    }
    result.per_frame.push_back(frame_accuracy);
  }
  if (result.camera_up.norm() > 0.0) result.camera_up.normalize();
  result.lidar = lidar.Result();
  result.lidar_paper = lidar_paper.Result();
  const ClassMap& class_map = source->class_map();
  if (result.frames_with_lidar > 0) result.lidar_breakdown = lidar_breakdown.Result(class_map);
  if (result.frames_with_exact_depth > 0) {
    result.exact_depth = exact.Result();
    result.exact_depth_paper = exact_paper.Result();
    result.exact_depth_breakdown = exact_breakdown.Result(class_map);
  }
  if (static_lidar_frames > 0) result.lidar_static = lidar_static.Result();
  if (static_exact_frames > 0) result.exact_depth_static = exact_static.Result();
  std::vector<std::string> sources;
  if (classes_from_images) sources.push_back("label images");
  if (classes_from_segmenter) sources.push_back("segmenter labels");
  if (classes_from_mesh) sources.push_back("mesh labels");
  for (std::size_t k = 0; k < sources.size(); ++k) {
    result.class_source = k == 0 ? sources[k] : result.class_source + " and " + sources[k];
  }
  const auto scene_mesh = info.root / "scene_mesh.ply";
  if (result.frames_with_exact_depth > 0 && std::filesystem::is_regular_file(scene_mesh)) {
    SurfaceMetricsOptions surface;
    surface.threshold_m = accuracy.surface_threshold_m;
    surface.area_samples = accuracy.surface_area_samples;
    result.scene =
        CompareSurfaces(mesh, ReadMeshPly(scene_mesh), truth_samples, surface, truth_sample_depths_m);
    result.scene_threshold_m = surface.threshold_m;
    result.scene_mesh_path = scene_mesh;
  }
  return result;
}

}  // namespace semap::app
