// COLMAP sparse models (a model folder such as sparse/0): cameras, images and points3D as text (.txt) or
// binary (.bin, little-endian), in COLMAP's own layout:
//   cameras:  CAMERA_ID MODEL WIDTH HEIGHT PARAMS...
//   images:   IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, then its POINTS2D as (X Y POINT3D_ID)...;
//             (QW..QZ, TX..TZ) is cam_from_world, POINT3D_ID -1 = no 3D point
//   points3D: POINT3D_ID X Y Z R G B ERROR, then its TRACK as (IMAGE_ID POINT2D_IDX)...
// Observations come from the tracks, their pixel from the image's POINTS2D entry; 2D points without a 3D
// point are not kept. Views are in the file's order (COLMAP writes them by IMAGE_ID). The reprojection
// ERROR is not kept (written as -1, "unknown").
// semap extension: per-point labels in points3D_labels.txt beside the model ("POINT3D_ID LABEL" lines, for
// every point), read when present, written when the reconstruction has labels.
#pragma once

#include <filesystem>

#include "io/file_error.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::io {

enum class ColmapEncoding { kText, kBinary };

// The semap extension's file of per-point labels, beside the model (see above).
inline constexpr const char* kColmapLabelsFile = "points3D_labels.txt";

// Binary when cameras.bin, images.bin and points3D.bin are all in `dir`, else text. Throws FileError /
// ParseError (naming the file, the line or record and the field) on a missing file, malformed or truncated
// entry, unknown camera model or wrong parameter count, duplicate id, non-finite number, quaternion that is
// not unit length, an image naming an unknown camera or 3D point, a track naming an unknown image or 2D
// point, or a 2D point that belongs to another 3D point than the track says.
SfmReconstruction ReadColmapModel(const std::filesystem::path& dir);
SfmReconstruction ReadColmapModel(const std::filesystem::path& dir, ColmapEncoding encoding);

// Writes cameras / images / points3D (+ points3D_labels.txt when labelled) into `dir` (created). Camera
// models must have a COLMAP equivalent and every observation a pixel position: std::invalid_argument
// otherwise; FileError on a write failure. Points without colour are written grey (128).
void WriteColmapModel(const std::filesystem::path& dir, const SfmReconstruction& reconstruction,
                      ColmapEncoding encoding = ColmapEncoding::kText);

}  // namespace semap::io
