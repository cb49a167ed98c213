// Streaming simplification: one frame's labelled points at a time, decided consistently with the last W
// frames (SimplifyOptions::window_frames).
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"
#include "engine/simplify/simplify.h"

namespace semap {

// For each new frame the simplifier builds a context = the points it kept from the last W frames (already
// decided: never removed again, never emitted again) followed by the new frame's points (the candidates),
// and runs the configured method on it:
// - class planes (RANSAC) are fitted on the whole context, so they are stable from frame to frame;
// - regions are centred on the new frame's points only but see every context point: densities D and p̃
//   include the kept points of the previous frames;
// - D̄ is the mean over the regions of the last W frames (including this one), not of this frame alone;
// - in LS/AS/ACS a region's quota counts the decided points it contains, so new points that fall on ground
//   or walls already covered by kept points mostly go; in PS the decided points of a region likewise scale
//   the candidates' P_c by max(0, 1 − decided / Σ P_c) (see probabilistic.cc), and the higher density d̃
//   widens P_I's Gaussian.
// W should cover the frames that see the same area (view depth / distance per frame): decided points older
// than W frames are forgotten, and an area still in view is then filled again as if new.
// The baselines (GB, voxel, hierarchy) also run on the context; decided points are never removed.
// The random generator of frame n is seeded from (options.seed, n), so a replay gives the same output.
//
// Thread-safety: not thread-safe (Process mutates the window); use one instance per stream. Different
// instances are independent. Process uses TBB internally for per-point work.
class WindowedSimplifier {
 public:
  WindowedSimplifier(const SimplifyOptions& options, ClassMap class_map);

  struct FrameResult {
    LabelledCloud kept;     // the kept points of the frame, every attribute carried, the frame's cameras
    SimplifyResult result;  // kept_indices into the frame; per-class counts of this frame; time
  };
  // Decides the points of one frame. `frame` needs camera_index/camera_centers_world for the normal
  // orientation (optional: without cameras normals are oriented along the class plane's normal).
  FrameResult Process(const LabelledCloud& frame);

  // Per-label counts summed over every processed frame.
  const std::vector<ClassSimplifyStats>& totals() const { return totals_; }
  std::uint64_t frames_processed() const { return frames_processed_; }
  // Forgets the window and the totals.
  void Reset();

 private:
  struct WindowFrame {
    LabelledCloud kept;
    std::vector<double> density_sum;           // per class group: sum of this frame's region densities
    std::vector<std::uint64_t> density_count;  // per class group: number of regions
  };
  SimplifyOptions options_;
  ClassMap class_map_;
  std::deque<WindowFrame> window_;
  std::vector<ClassSimplifyStats> totals_;
  std::uint64_t frames_processed_ = 0;
};

}  // namespace semap
