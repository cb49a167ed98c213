// `semap render`: a mesh file drawn from above (or obliquely) by semap's software renderer
// (engine/eval/top_view.h): vertex colours, height or distance to a true surface.
#pragma once

#include <filesystem>
#include <string>

#include "engine/eval/top_view.h"

namespace semap::app {

struct RenderRequest {
  std::filesystem::path mesh;  // .ply or .off
  std::filesystem::path out;   // the PNG
  // World up: "x", "-x", "y", "-y", "z", "-z", or "auto": the axis along which the mesh's bounding box is
  // thinnest, taken as up for x and z (KITTI raw: z up) and as down for y (camera frames, KITTI odometry).
  std::string up = "auto";
  TopViewColour colour = TopViewColour::kMesh;
  std::filesystem::path truth;  // the true surface; required for TopViewColour::kError
  TopViewOptions view;          // angles and image size (its colour is `colour`)
};

// Draws the mesh as asked and writes the PNG; logs what it drew. Throws io::FileError naming a file that
// cannot be read or written.
void RenderMeshFile(const RenderRequest& request);

}  // namespace semap::app
