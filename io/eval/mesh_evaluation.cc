#include "io/eval/mesh_evaluation.h"

#include <cstdio>

#include "io/kitti/ground_truth.h"
#include "io/mesh/ply_off.h"

namespace semap::io {
namespace {

// Exact depth map of frame `id` of a generated sequence (depth/data/%010d.png beside image_02), if any.
std::optional<std::filesystem::path> ExactDepthPath(const SequenceInfo& info, std::int64_t id) {
  char name[32];
  std::snprintf(name, sizeof(name), "%010lld.png", static_cast<long long>(id));
  const auto path = info.root / "depth" / "data" / name;
  if (std::filesystem::is_regular_file(path)) return path;
  return std::nullopt;
}

}  // namespace

MeshEvaluation EvaluateMesh(const Mesh& mesh, const std::filesystem::path& dataset, FrameSourceOptions input,
                            const DepthAccuracyOptions& accuracy) {
  input.load_velodyne = true;
  const SequenceInfo info = DescribeDataset(dataset, input);
  auto source = OpenFrameSource(dataset, input);
  DepthAccuracyAccumulator lidar(accuracy);
  DepthAccuracyAccumulator exact(accuracy);
  std::vector<Eigen::Vector3d> truth_samples;  // the exact depth maps' points, in the world frame
  MeshEvaluation result;
  result.off_bytes = OffSizeBytes(mesh);
  result.vertices = mesh.num_vertices();
  result.triangles = mesh.num_triangles();
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
    const cv::Mat mesh_depth = RenderDepth(mesh, frame->calibration, *frame->world_from_cam);
    FrameAccuracy frame_accuracy;
    frame_accuracy.frame_id = frame->id;
    if (frame->velodyne) {
      DepthAccuracyAccumulator one(accuracy);
      one.Add(LidarDepthImage(*frame->velodyne, frame->calibration, accuracy), mesh_depth);
      frame_accuracy.lidar = one.Result();
      lidar.Merge(one);
      ++result.frames_with_lidar;
    }
    if (const auto path = ExactDepthPath(info, frame->id)) {
      DepthAccuracyAccumulator one(accuracy);
      const cv::Mat exact_depth = ReadDepthPngMm(*path);
      one.Add(exact_depth, mesh_depth);
      const int stride = accuracy.surface_pixel_stride;
      for (int v = stride / 2; v < exact_depth.rows; v += stride) {
        for (int u = stride / 2; u < exact_depth.cols; u += stride) {
          const float z = exact_depth.at<float>(v, u);
          if (z < accuracy.min_depth_m || z > accuracy.max_depth_m) continue;
          truth_samples.push_back(*frame->world_from_cam * frame->calibration.Unproject(u, v, z));
        }
      }
      frame_accuracy.exact_depth = one.Result();
      exact.Merge(one);
      ++result.frames_with_exact_depth;
    }
    result.per_frame.push_back(frame_accuracy);
  }
  if (result.camera_up.norm() > 0.0) result.camera_up.normalize();
  result.lidar = lidar.Result();
  if (result.frames_with_exact_depth > 0) result.exact_depth = exact.Result();
  const auto scene_mesh = info.root / "scene_mesh.ply";
  if (result.frames_with_exact_depth > 0 && std::filesystem::is_regular_file(scene_mesh)) {
    SurfaceMetricsOptions surface;
    surface.threshold_m = accuracy.surface_threshold_m;
    surface.area_samples = accuracy.surface_area_samples;
    result.scene = CompareSurfaces(mesh, ReadMeshPly(scene_mesh), truth_samples, surface);
    result.scene_threshold_m = surface.threshold_m;
    result.scene_mesh_path = scene_mesh;
  }
  return result;
}

}  // namespace semap::io
