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
    const cv::Mat mesh_depth = RenderDepth(mesh, frame->calibration, *frame->world_from_cam);
    if (frame->velodyne) {
      lidar.Add(LidarDepthImage(*frame->velodyne, frame->calibration, accuracy), mesh_depth);
      ++result.frames_with_lidar;
    }
    if (const auto path = ExactDepthPath(info, frame->id)) {
      exact.Add(ReadDepthPngMm(*path), mesh_depth);
      ++result.frames_with_exact_depth;
    }
  }
  result.lidar = lidar.Result();
  if (result.frames_with_exact_depth > 0) result.exact_depth = exact.Result();
  return result;
}

}  // namespace semap::io
