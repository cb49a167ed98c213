// Camera model names of the formats and the exact translations between them (for the writers).
#pragma once

#include <optional>
#include <string>

#include "io/sfm/sfm_reconstruction.h"

namespace semap::io::sfm_internal {

struct ColmapModel {
  int id = 0;        // COLMAP's CameraModelId, as stored in cameras.bin
  const char* name;  // as written in cameras.txt
  int num_params = 0;
};

std::optional<ColmapModel> ColmapModelByName(const std::string& name);
std::optional<ColmapModel> ColmapModelById(int id);

// OpenMVG intrinsic types (also used by the SLAM JSON): the name of the JSON array holding the distortion
// after focal_length and principal_point ("" = none), and its length. Params are f, cx, cy, distortion...
struct OpenMvgModel {
  const char* name;
  const char* distortion_field;
  int distortion_size = 0;
};
std::optional<OpenMvgModel> OpenMvgModelByName(const std::string& name);

// The same camera in COLMAP's / OpenMVG's naming when there is an exact equivalent (SIMPLE_PINHOLE ↔
// pinhole, PINHOLE with fx = fy → pinhole, SIMPLE_RADIAL ↔ pinhole_radial_k1, RADIAL ↔ pinhole_radial_k3
// with k3 = 0); models already in the target naming (and, for OpenMVG, unknown types read without
// parameters) are returned as they are. Throws std::invalid_argument
// naming the model otherwise.
SfmIntrinsics AsColmapModel(const SfmIntrinsics& k);
SfmIntrinsics AsOpenMvgModel(const SfmIntrinsics& k);

}  // namespace semap::io::sfm_internal
