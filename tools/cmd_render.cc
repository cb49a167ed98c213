// `semap render MESH --out view.png`: the mesh as a user sees it from above (or obliquely), drawn by semap's
// software renderer (engine/eval/top_view.h): vertex colours, height or distance to a true surface.
#include <filesystem>

#include <spdlog/spdlog.h>

#include "engine/eval/surface_metrics.h"
#include "engine/eval/top_view.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"
#include "tools/cli_common.h"

namespace semap::tools {
namespace {

struct RenderArgs {
  CommonArgs common;
  std::string mesh;
  std::string out;
  std::string up = "auto";
  std::string colour = "mesh";
  std::string truth;
  TopViewOptions view;
};

Mesh ReadMesh(const std::filesystem::path& path) {
  return path.extension() == ".off" ? io::ReadMeshOff(path) : io::ReadMeshPly(path);
}

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

int Render(const RenderArgs& args) {
  const Mesh mesh = ReadMesh(args.mesh);
  const Eigen::Vector3d up = UpAxis(args.up, mesh);
  TopViewOptions options = args.view;
  options.colour = args.colour == "height" ? TopViewColour::kHeight
                   : args.colour == "error" ? TopViewColour::kError
                                            : TopViewColour::kMesh;
  std::unique_ptr<SurfaceDistance> to_truth;
  std::function<double(const Eigen::Vector3d&)> distance;
  if (options.colour == TopViewColour::kError) {
    if (args.truth.empty()) {
      spdlog::error("--colour error needs --truth MESH (e.g. a generated sequence's scene_mesh.ply)");
      return kExitUsage;
    }
    to_truth = std::make_unique<SurfaceDistance>(ReadMesh(args.truth));
    distance = [&](const Eigen::Vector3d& p) { return (*to_truth)(p); };
  }
  const TopView view = RenderTopView(mesh, up, options, distance);
  io::WritePng(args.out, view.image);
  spdlog::info("{}: {} triangles seen along up = ({:g}, {:g}, {:g}), {} coloured, {:.3f} m/px, {} px covered -> {}",
               args.mesh, mesh.num_triangles(), up.x(), up.y(), up.z(), TopViewColourName(options.colour),
               view.metres_per_px, cv::countNonZero(view.triangle >= 0), args.out);
  return kExitOk;
}

}  // namespace

void RegisterRenderCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Draw a mesh seen from above (orthographic along the up axis) or "
                                           "obliquely, as a PNG: vertex colours, height, or distance to a true "
                                           "surface");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("MESH", args->mesh, "mesh file (.ply or .off)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "PNG file to write")->required();
  cmd->add_option("--up", args->up,
                  "world up axis: z, -y (KITTI odometry / camera frames), ...; auto = the mesh's thinnest axis "
                  "(y taken as down)")
      ->check(CLI::IsMember({"auto", "x", "-x", "y", "-y", "z", "-z"}))
      ->capture_default_str();
  cmd->add_option("--colour", args->colour, "mesh (vertex colours) | height | error (needs --truth)")
      ->check(CLI::IsMember({"mesh", "height", "error"}))
      ->capture_default_str();
  cmd->add_option("--truth", args->truth, "true surface for --colour error (e.g. scene_mesh.ply)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--elevation", args->view.elevation_deg, "view angle above the horizon in degrees (90 = from above)")
      ->capture_default_str();
  cmd->add_option("--azimuth", args->view.azimuth_deg, "turn of the view about the up axis in degrees")
      ->capture_default_str();
  cmd->add_option("--width", args->view.max_width_px, "largest image width in px")->capture_default_str();
  cmd->add_option("--height", args->view.max_height_px, "largest image height in px")->capture_default_str();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Render(*args); }); });
}

}  // namespace semap::tools
