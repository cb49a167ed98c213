// Where a run's camera poses come from (input.poses): the sequence's own, or stereo visual odometry.
#pragma once

namespace semap::app {

enum class PoseSource {
  kAuto,      // the sequence's poses when it has them, else visual odometry
  kFile,      // the sequence's pose file (KITTI odometry poses/NN.txt): error without one
  kOxts,      // the sequence's OXTS GPS/IMU poses (KITTI raw): error without them
  kOdometry,  // visual odometry; poses the sequence has are left out of the map (and kept for comparison)
};

const char* PoseSourceName(PoseSource source);

struct PoseInputOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  PoseSource poses = PoseSource::kAuto;
  bool compare_odometry = false;

  // Bound into the input section (input.poses). Visitor: Field(key, T*, text) and Enum(key, E*, {...}, text).
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Enum(
        "poses", &poses,
        {{"auto", PoseSource::kAuto},
         {"file", PoseSource::kFile},
         {"oxts", PoseSource::kOxts},
         {"odometry", PoseSource::kOdometry}},
        "where the map's camera poses come from: auto = the sequence's own when it has them, else stereo "
        "visual odometry; file = its pose file (KITTI odometry poses/NN.txt); oxts = its OXTS GPS/IMU poses "
        "(KITTI raw); odometry = visual odometry (the sequence's poses are not used; see odometry.*)");
    v.Field(
        "compare_odometry", &compare_odometry,
        "when the map uses the sequence's poses, also run visual odometry beside them: its trajectory and "
        "per-frame figures are written for comparison (semap eval-poses)");
  }

  void Check() const {}
};

// input.one_frame_preset: how a run of exactly one frame is configured.
struct OneFrameInputOptions {
  bool one_frame_preset = true;

  // Bound into the input section. Visitor: Field(key, T*, text).
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("one_frame_preset", &one_frame_preset,
            "a `semap run` of exactly one frame takes config/one_frame.yaml's values (every matched pixel a "
            "point, a seen band of 1 sigma) where the config file and --set leave them: no second view will "
            "confirm or refine a one-frame map (bench/results/map-accuracy.md, one-frame maps)");
  }

  void Check() const {}
};

}  // namespace semap::app
