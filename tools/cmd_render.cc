// `semap render MESH --out view.png`: the mesh as a user sees it from above (or obliquely), drawn by semap's
// software renderer (engine/eval/top_view.h): vertex colours, height or distance to a true surface.
#include <spdlog/spdlog.h>

#include "app/eval/render_mesh.h"
#include "engine/eval/top_view.h"
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

int Render(const RenderArgs& args) {
  app::RenderRequest request{args.mesh, args.out, args.up, TopViewColour::kMesh, args.truth, args.view};
  if (args.colour == "height") request.colour = TopViewColour::kHeight;
  if (args.colour == "error") {
    if (args.truth.empty()) {
      spdlog::error("--colour error needs --truth MESH (e.g. a generated sequence's scene_mesh.ply)");
      return kExitUsage;
    }
    request.colour = TopViewColour::kError;
  }
  app::RenderMeshFile(request);
  return kExitOk;
}

}  // namespace

void RegisterRenderCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render",
                                 "Draw a mesh seen from above (orthographic along the up axis) or "
                                 "obliquely, as a PNG: vertex colours, height, or distance to a true "
                                 "surface");
  AddCommonOptions(cmd, &args->common);
  cmd->add_option("MESH", args->mesh, "mesh file (.ply or .off)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "PNG file to write")->required();
  cmd->add_option(
         "--up", args->up,
         "world up axis: z, -y (KITTI odometry / camera frames), ...; auto = the mesh's thinnest axis "
         "(y taken as down)")
      ->check(CLI::IsMember({"auto", "x", "-x", "y", "-y", "z", "-z"}))
      ->capture_default_str();
  cmd->add_option("--colour", args->colour, "mesh (vertex colours) | height | error (needs --truth)")
      ->check(CLI::IsMember({"mesh", "height", "error"}))
      ->capture_default_str();
  cmd->add_option("--truth", args->truth, "true surface for --colour error (e.g. scene_mesh.ply)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--elevation", args->view.elevation_deg,
                  "view angle above the horizon in degrees (90 = from above)")
      ->capture_default_str();
  cmd->add_option("--azimuth", args->view.azimuth_deg, "turn of the view about the up axis in degrees")
      ->capture_default_str();
  cmd->add_option("--width", args->view.max_width_px, "largest image width in px")->capture_default_str();
  cmd->add_option("--height", args->view.max_height_px, "largest image height in px")->capture_default_str();
  cmd->callback([=]() { *exit_code = RunGuarded(args->common, [&]() { return Render(*args); }); });
}

}  // namespace semap::tools
