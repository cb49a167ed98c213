// Binds every stage's options struct to its config section. The keys and their texts are each options
// struct's own (its Describe()); this file names the sections and orders them.
#include "app/config/config.h"
#include "engine/core/check.h"

namespace semap::app {

using io::Section;

namespace {

template <typename Options>
Section MakeSection(std::string name, std::string doc, Options& options) {
  Section s{std::move(name), std::move(doc), {}, [&options]() { options.Check(); }};
  options.Describe(s.binder);
  return s;
}

}  // namespace

const char* PoseSourceName(PoseSource source) {
  switch (source) {
    case PoseSource::kAuto:
      return "auto";
    case PoseSource::kFile:
      return "file";
    case PoseSource::kOxts:
      return "oxts";
    case PoseSource::kOdometry:
      return "odometry";
  }
  return "?";
}

std::vector<Section> BindSections(Config& c) {
  // In the order of the data flow.
  std::vector<Section> s;
  s.push_back(MakeSection("input", "Input: where frames come from and what is loaded with them.", c.input));
  c.pose_input.Describe(s.back().binder);  // input.poses: the app's, not the frame source's
  c.one_frame.Describe(s.back().binder);   // input.one_frame_preset: the app's too
  s.push_back(MakeSection("odometry",
                          "Stereo visual odometry: poses from the images (input.poses = odometry, or auto "
                          "on a sequence without poses).",
                          c.odometry));
  s.push_back(
      MakeSection("depth", "Depth: stereo matching (OpenCV SGBM) and the per-frame point cloud.", c.depth));
  s.push_back(
      MakeSection("plane_sweep",
                  "Plane-sweep depth of a multi-view set's frames (no stereo pair): each frame against "
                  "its input.neighbour_views nearest views (depth.half_resolution sweeps at half size).",
                  c.plane_sweep));
  s.push_back(MakeSection("semantics", "Semantics: where the per-pixel labels come from (first-camera rule).",
                          c.semantics));
  s.push_back(MakeSection(
      "simplify", "Semantic simplification of ground and walls (paper Sec. III) and baselines.", c.simplify));
  s.push_back(MakeSection(
      "map", "Delaunay map: visibility votes, manifold extraction, incremental update, memory bound.",
      c.map));
  s.push_back(MakeSection("synth", "Synthetic KITTI-format sequences (`semap synth`).", c.synth));
  s.push_back(
      MakeSection("pipeline", "Streaming engine: threads, queues, real-time or exhaustive.", c.pipeline));
  s.push_back(MakeSection("output", "Files written by `semap run`.", c.output));
  s.push_back(MakeSection("lcm", "LCM publishing (non-blocking, own thread).", c.lcm));
  s.push_back(MakeSection("split",
                          "Split runs: depth nodes (semap run --publish-depth) and a map node (semap map) "
                          "joined over LCM.",
                          c.split));
  s.push_back(MakeSection("depth_frames",
                          "A split run's depth frames over LCM: each frame cut into bands of rows, each band "
                          "compressed losslessly (zstd) into one datagram.",
                          c.depth_frames));
  s.push_back(MakeSection(
      "eval", "Accuracy of a mesh against Velodyne / exact depth (semap eval, table, compare).", c.eval));
  return s;
}

}  // namespace semap::app
