// A split run: depth nodes (`semap run --publish-depth`) compute each frame's depth and labels and publish
// them over LCM; a map node (`semap map`) builds the map from them. Both read this section; how the frames
// are encoded is the depth_frames section's (io::DepthFrameOptions).
#pragma once

#include "engine/core/options.h"

namespace semap::app {

struct SplitOptions {
  // Each field's key and meaning: Describe() below, once.
  int run_id = 1;
  double wait_s = 1.5;
  double idle_end_s = 10.0;
  double first_frame_timeout_s = 120.0;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h).
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("run_id", &run_id,
            "the run's id: the map node takes the depth frames of its own run id only (others are counted "
            "and skipped); start every node of one run with the same id",
            AtLeast(1));
    // Several depth nodes finish their frames out of order by up to a frame's depth time; a longer wait
    // integrates slow frames rather than losing them, a shorter one keeps the mesh younger after a loss.
    v.Field("wait_s", &wait_s,
            "map node: a frame still incomplete this long after a later frame arrived whole is given up "
            "(counted as dropped, reason lost), s",
            Above(0));
    v.Field("idle_end_s", &idle_end_s,
            "map node: the run ends when no depth frame has arrived for this long (the depth nodes finished "
            "or died; the frames still missing are lost), s",
            Above(0));
    v.Field("first_frame_timeout_s", &first_frame_timeout_s,
            "map node: how long to wait for the first whole depth frame before giving up, s", Above(0));
  }

  void Check() const { CheckDeclaredRanges(*this); }
};

}  // namespace semap::app
