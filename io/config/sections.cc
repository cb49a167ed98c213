// Binds every stage's options struct to its config section. One Bind() per options struct;
// the doc strings here are what config/default.yaml shows.
#include "engine/core/check.h"
#include "io/config/config.h"

namespace semap::io {
namespace {

void Bind(FieldBinder& b, FrameSourceOptions& o) {
  b.Enum("layout", &o.layout,
         {{"auto", DatasetLayout::kAuto},
          {"kitti_raw", DatasetLayout::kKittiRaw},
          {"kitti_odometry", DatasetLayout::kKittiOdometry},
          {"kitti_stereo2015", DatasetLayout::kKittiStereo2015}},
         "dataset layout; auto detects it from the folder");
  b.Field("first_frame", &o.first_frame, "first frame index to read (0-based, as numbered on disk)");
  b.Field("max_frames", &o.max_frames, "number of frames to read; 0 = to the end of the sequence");
  b.Field("load_velodyne", &o.load_velodyne, "read Velodyne scans when present (evaluation only)");
  b.Field("labels_dir", &o.labels_dir,
          "folder of label PNGs, one per frame with the image's stem; empty = the dataset's own if any");
  b.Field("class_map", &o.class_map, "YAML class map of the label ids; empty = Cityscapes 20 classes");
  b.Enum("odometry_pair", &o.odometry_pair,
         {{"auto", CameraPair::kAuto}, {"gray", CameraPair::kGray}, {"color", CameraPair::kColor}},
         "KITTI odometry: stereo pair to read (gray image_0/1, colour image_2/3; auto = colour if present)");
  b.Field("default_frame_period_s", &o.default_frame_period_s,
          "frame period for timestamps when the dataset has none, s (KITTI records at 10 Hz)");
}

template <typename Options>
Section MakeSection(std::string name, std::string doc, Options& options) {
  Section s{std::move(name), std::move(doc), {}, [&options]() { options.Check(); }};
  Bind(s.binder, options);
  return s;
}

}  // namespace

std::vector<Section> BindSections(Config& c) {
  std::vector<Section> s;
  s.push_back(MakeSection("input", "Input: where frames come from and what is loaded with them.", c.input));
  return s;
}

}  // namespace semap::io
