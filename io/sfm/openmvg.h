// OpenMVG's sfm_data.json (cereal JSON, sfm_data_version "0.2" / "0.3"): "views" (key = view id; data with
// filename, id_intrinsic, id_pose), "intrinsics" (polymorphic: pinhole, pinhole_radial_k1/k3,
// pinhole_brown_t2, fisheye, spherical), "extrinsics" (key = pose id; rotation world → camera row by row,
// centre), "structure" (key = point id; X and observations {key = view id, value {id_feat, x}}).
// Views whose pose is undefined (not reconstructed) are left out. semap extension: an optional integer
// "label" in a structure value (every point has one or none). "x" is optional when reading and left out
// when writing an observation without pixel position.
#pragma once

#include <filesystem>

#include "io/file_error.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::io {

// Throws FileError / ParseError (naming the entry, e.g. "structure[12] (key 40)", and the field) on a
// missing or malformed field, duplicate key, observation of a view that does not exist or has no pose,
// unknown intrinsic, non-finite number, or a rotation that is not orthonormal.
SfmReconstruction ReadOpenMvgJson(const std::filesystem::path& path);

// Writes version "0.3" with one pose per view (pose id = view id). Camera models must have an OpenMVG
// equivalent (internal/camera_models.h): std::invalid_argument otherwise; FileError on a write failure.
void WriteOpenMvgJson(const std::filesystem::path& path, const SfmReconstruction& reconstruction);

}  // namespace semap::io
