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
}

void Bind(FieldBinder& b, MapOptions& o) {
  b.Field("sigma_free_m", &o.sigma_free_m, "σ_free of the free-space weight 1 - exp(-d²/(2σ²)), metres");
  b.Field("sigma_matter_m", &o.sigma_matter_m, "σ_matter of the matter weight 1 - exp(-d²/(2σ²)), metres");
  b.Field("ray_extension_factor", &o.ray_extension_factor,
          "rays are extended behind their point by this many σ_matter (matter votes)");
  b.Field("max_ray_length_m", &o.max_ray_length_m,
          "points farther than this from their camera are dropped; 0 = no limit");
  b.Field("merge_distance_m", &o.merge_distance_m,
          "a new point this close to an existing one is merged into it (only its ray is added); 0 = exact "
          "duplicates only");
  b.Field("grow_passes", &o.grow_passes,
          "region-growing passes retrying the cells the manifold test refused");
  b.Field("steiner_spacing_m", &o.steiner_spacing_m, "spacing of the bounding Steiner lattice, metres");
  b.Field("steiner_margin_cubes", &o.steiner_margin_cubes, "lattice cubes kept around each point and camera");
  b.Field("drop_steiner_triangles", &o.drop_steiner_triangles,
          "leave triangles touching a Steiner vertex out of the mesh");
  b.Field("finalise_age_frames", &o.finalise_age_frames,
          "finalise (emit once, then release) points older than this many frames; 0 = never by age");
  b.Field("finalise_distance_m", &o.finalise_distance_m,
          "finalise points farther than this from the latest camera; 0 = never by distance");
  b.Field("finalise_min_age_frames", &o.finalise_min_age_frames, "minimum age before finalising by distance");
  b.Field("finalise_every_frames", &o.finalise_every_frames,
          "run finalisation every this many frames (amortises the retracing it causes)");
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
  s.push_back(MakeSection(
      "map", "Delaunay map: visibility votes, manifold extraction, incremental update, memory bound.",
      c.map));
  return s;
}

}  // namespace semap::io
