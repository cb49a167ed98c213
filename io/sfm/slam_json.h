// The ORB-SLAM-style JSON read by the 2018 incremental manifold mapper (Piazza et al., RA-L 2018),
// slam_data_version "0.2" or "0.3":
//   { "slam_data_version": "0.3", "root_path": "...",
//     "intrinsics": [ { "intrinsicId": 0, "value": { "polymorphic_name": "pinhole",
//                       "ptr_wrapper": { "data": { "width", "height", "focal_length", "principal_point" } } }
//                       } ],
//     "views": [ { "viewId": 3, "local_path": "", "filename": "000003.png", "width", "height",
//     "id_intrinsic": 0,
//                  "extrinsic": { "rotation": [[...], [...], [...]], "center": [x, y, z] },
//                  "observations": [ { "pointId": 17, "X": [x, y, z], "x": [u, v] }, ... ] }, ... ] }
// `rotation` is world → camera, row by row (x_cam = R (X − center)). A point appears in the observations of
// every view that sees it, each time with its position X: the reader keeps the last one (the SLAM system's
// latest estimate). "x" (pixel) is optional. semap extension: an optional integer "label" per observation
// (all observations have one or none; a point takes its last one).
#pragma once

#include <filesystem>

#include "io/file_error.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::io {

// Throws FileError / ParseError (naming the view entry and the field) on a missing or malformed field,
// duplicate viewId, unknown id_intrinsic, non-finite number or a rotation that is not orthonormal.
SfmReconstruction ReadSlamJson(const std::filesystem::path& path);

// Writes version "0.3"; every view needs intrinsics with an OpenMVG-style model (COLMAP pinhole models are
// translated, see internal/camera_models.h). Throws std::invalid_argument for a reconstruction the format
// cannot hold, FileError when the file cannot be written.
void WriteSlamJson(const std::filesystem::path& path, const SfmReconstruction& reconstruction);

}  // namespace semap::io
