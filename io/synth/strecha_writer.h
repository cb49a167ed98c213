// Writes a generated multi-view set (engine/sim/multi_view_set.h) in the Strecha layout that
// io/sfm/strecha.h reads, with its exact ground truth.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "engine/sim/multi_view_set.h"
#include "engine/sim/synthetic_sequence.h"

namespace semap::io {

struct StrechaWriteSummary {
  int num_views = 0;
  sim::LabelHistogram label_pixels;  // over all label images
};

// The name of view `view`'s files: "NNNN" (four digits at least).
std::string StrechaViewStem(int view);

// Writes every view of `set` under `root` (created if missing; existing files are overwritten):
//   ROOT/images/NNNN.png                     (BGR colour)
//   ROOT/images/K.txt                        (the intrinsics, 3 rows, as fountain-P11 has; not a view)
//   ROOT/gt_dense_cameras/NNNN.png.camera    (K, distortion 0 0 0, R = camera-to-world rotation, C, size;
//                                             FormatStrechaCamera, exact to the double)
//   ROOT/labels/NNNN.png                     (uint8 Cityscapes ids; 11, sky, where no surface)
//   ROOT/depth/NNNN.png                      (uint16 exact depth in mm, camera z; 0 = none or >= 65.535 m)
//   ROOT/scene_mesh.ply                      (binary, double precision, per-vertex labels, world frame)
// Views are rendered and written in parallel (TBB); the bytes do not depend on the thread count.
// `progress(done, total)` is called after each view (from worker threads, serialised). Throws FileError
// naming the path when a file cannot be written.
StrechaWriteSummary WriteSyntheticStrecha(const sim::MultiViewSet& set, const std::filesystem::path& root,
                                          const std::function<void(int, int)>& progress = {});

}  // namespace semap::io
