// The Strecha multi-view layout (EPFL fountain-P11, Herz-Jesu, ...), at any resolution: images in
// `images/` and one camera per image in `gt_dense_cameras/<image file name>.camera`, 9 lines of numbers:
//   lines 1–3  K, the intrinsics (pixels), row by row;
//   line 4     the radial distortion (must be 0 0 0: semap reads undistorted images only);
//   lines 5–7  R, the camera-to-world rotation, row by row;
//   line 8     C, the camera centre in the world (m);
//   line 9     the image's width and height (px).
// A world point X projects as x ~ K Rᵀ (X − C): world_from_cam has rotation R and translation C.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "io/file_error.h"
#include "io/frame_source.h"

namespace semap::io {

// One calibrated view of a Strecha set.
struct StrechaView {
  std::filesystem::path image;        // the image file
  std::filesystem::path camera_file;  // its .camera file
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Pose3d world_from_cam = Pose3d::Identity();
  int width_px = 0;
  int height_px = 0;
};

// Reads one .camera file (image and size check left out: `image` stays empty). Throws FileError when it
// cannot be read, ParseError naming the file and the line of the first problem: a line missing, a value
// that is not a number, too few or too many values, a non-zero distortion, a K that is not upper triangular
// with last row 0 0 1 and positive focal lengths, an R that is not a rotation (|RᵀR − I| or |det R − 1|
// above 1e-3), a size that is not two positive integers.
StrechaView ReadStrechaCamera(const std::filesystem::path& camera_file);

// The text of a .camera file (the 9 lines above) of a view with intrinsics K, pose world_from_cam and size
// width × height, every number in %.17g: ReadStrechaCamera reads back exactly the K, R and C written.
std::string FormatStrechaCamera(const Eigen::Matrix3d& K, const Pose3d& world_from_cam, int width_px,
                                int height_px);

// The view images of a Strecha set: root/images' .jpg / .jpeg / .png files (any case), sorted by name; the
// i-th is view i. Throws FileError when root/images is not a folder.
std::vector<std::filesystem::path> StrechaImageFiles(const std::filesystem::path& root);

// Reads a Strecha set from its root folder: every .jpg / .png file of root/images (by name; other files
// such as K.txt are not views) with its camera. Throws FileError when a folder or an image's camera file is
// missing or an image cannot be read, ParseError (as ReadStrechaCamera) for a malformed camera file or one
// whose line 9 differs from its image's size. Decodes every image once to check its size.
std::vector<StrechaView> ReadStrechaSet(const std::filesystem::path& root);

// True when `root` holds the layout's two folders (images/, gt_dense_cameras/).
bool IsStrechaSet(const std::filesystem::path& root);

// The set at `root` as a frame source (DatasetLayout::kStrecha): one frame per view in file-name order, its
// id the view's index in the set, its timestamp id × options.default_frame_period_s. A frame carries its
// colour image as `left` (no right image), its camera, and options.neighbour_views neighbour views in grey
// (SelectNeighbourViews over the whole set: the nearest cameras looking the same way), with
// calibration.baseline_m the distance to the nearest of them; labels from options.labels_dir or
// root/labels when present. Throws what ReadStrechaSet throws, FileError for a K with a skew, and FileError
// / InvalidOption as OpenFrameSource does for the frame selection and the class map.
std::unique_ptr<FrameSource> OpenStrechaSource(const std::filesystem::path& root,
                                               const FrameSourceOptions& options);

}  // namespace semap::io
