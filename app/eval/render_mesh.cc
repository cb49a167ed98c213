#include "app/eval/render_mesh.h"

#include <spdlog/spdlog.h>

#include <functional>
#include <memory>

#include "engine/core/check.h"
#include "engine/eval/surface_metrics.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

// The up axis named on the command line, or (auto) guessed from the mesh: the axis along which its bounding
// box is thinnest (a street is longer and wider than high), taken as up for x and z (KITTI raw's IMU world
// frame: z up) and as down for y (camera frames, KITTI odometry: y down).
Eigen::Vector3d UpAxis(const std::string& name, const Mesh& mesh) {
  if (name != "auto") {
    const double sign = name[0] == '-' ? -1.0 : 1.0;
    return sign * Eigen::Vector3d::Unit(name.back() - 'x');
  }
  if (mesh.vertices.empty()) return Eigen::Vector3d::UnitZ();
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  int axis = 0;
  (hi - lo).minCoeff(&axis);
  return (axis == 1 ? -1.0 : 1.0) * Eigen::Vector3d::Unit(axis);
}

}  // namespace

void RenderMeshFile(const RenderRequest& args) {
  const Mesh mesh = io::ReadMesh(args.mesh);
  const Eigen::Vector3d up = UpAxis(args.up, mesh);
  TopViewOptions options = args.view;
  options.colour = args.colour;
  std::unique_ptr<SurfaceDistance> to_truth;
  std::function<double(const Eigen::Vector3d&)> distance;
  if (options.colour == TopViewColour::kError) {
    SEMAP_ASSERT(!args.truth.empty(), "an error colouring needs the true surface");
    to_truth = std::make_unique<SurfaceDistance>(io::ReadMesh(args.truth));
    distance = [&](const Eigen::Vector3d& p) { return (*to_truth)(p); };
  }
  const TopView view = RenderTopView(mesh, up, options, distance);
  io::WritePng(args.out, view.image);
  spdlog::info(
      "{}: {} triangles seen along up = ({:g}, {:g}, {:g}), {} coloured, {:.3f} m/px, {} px covered -> {}",
      args.mesh.string(), mesh.num_triangles(), up.x(), up.y(), up.z(), TopViewColourName(options.colour),
      view.metres_per_px, cv::countNonZero(view.triangle >= 0), args.out.string());
}

}  // namespace semap::app
