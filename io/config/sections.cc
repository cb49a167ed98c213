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

void Bind(FieldBinder& b, sim::SynthOptions& o) {
  b.Enum("preset", &o.preset,
         {{"urban", sim::ScenePreset::kUrban},
          {"vegetated", sim::ScenePreset::kVegetated},
          {"mixed", sim::ScenePreset::kMixed}},
         "scene composition: urban (long facades, wide ground), vegetated (trees, bushes, cars), mixed");
  b.Field("num_frames", &o.num_frames, "number of frames to generate");
  b.Field("seed", &o.seed, "seed of every random choice; the same seed gives byte-identical output");
  b.Field("speed_mps", &o.speed_mps, "vehicle speed in m/s");
  b.Field("num_turns", &o.num_turns, "90-degree turns at intersections (fewer if the drive is too short)");
  b.Field("frame_rate_hz", &o.frame_rate_hz, "camera and scanner rate in Hz (KITTI: 10)");
  b.Field("body_wobble_rad", &o.body_wobble_rad, "amplitude of the vehicle's roll/pitch oscillation (rad)");
  b.Field("block_pitch_m", &o.block_pitch_m, "distance between parallel street centre lines (m)");
  b.Field("road_width_m", &o.road_width_m, "carriageway width, kerb to kerb (m)");
  b.Field("sidewalk_width_m", &o.sidewalk_width_m, "sidewalk width (m)");
  b.Field("curb_height_m", &o.curb_height_m, "sidewalk height above the road (m)");
  b.Field("lane_offset_m", &o.lane_offset_m, "vehicle offset to the right of the street centre line (m)");
  b.Field("turn_radius_m", &o.turn_radius_m, "radius of the arcs driven at turns (m)");
  b.Field("content_distance_m", &o.content_distance_m, "blocks closer than this to the drive get full detail (m)");
  b.Field("image_width_px", &o.image_width_px, "image width (px)");
  b.Field("image_height_px", &o.image_height_px, "image height (px)");
  b.Field("fx_px", &o.fx_px, "focal length x (px)");
  b.Field("fy_px", &o.fy_px, "focal length y (px)");
  b.Field("cx_px", &o.cx_px, "principal point x (px)");
  b.Field("cy_px", &o.cy_px, "principal point y (px)");
  b.Field("baseline_m", &o.baseline_m, "stereo baseline (m)");
  b.Field("near_m", &o.near_m, "nearest rendered depth (m)");
  b.Field("image_noise_sigma", &o.image_noise_sigma, "Gaussian image noise, in 8-bit grey levels");
  b.Field("blur_sigma_px", &o.blur_sigma_px, "Gaussian optical blur (px), 0 = none");
  b.Field("right_exposure_gain", &o.right_exposure_gain, "exposure of the right camera relative to the left");
  b.Field("exposure_variation", &o.exposure_variation, "relative slow exposure drift over frames");
  b.Field("vignetting", &o.vignetting, "relative brightness loss in the image corners");
  b.Field("lidar_beams", &o.lidar_beams, "scanner beams (HDL-64: 64)");
  b.Field("lidar_azimuth_steps", &o.lidar_azimuth_steps, "rays per beam and revolution");
  b.Field("lidar_top_deg", &o.lidar_top_deg, "elevation of the top beam (deg)");
  b.Field("lidar_bottom_deg", &o.lidar_bottom_deg, "elevation of the bottom beam (deg)");
  b.Field("lidar_min_range_m", &o.lidar_min_range_m, "minimum scanner range (m)");
  b.Field("lidar_max_range_m", &o.lidar_max_range_m, "maximum scanner range (m)");
  b.Field("lidar_range_noise_m", &o.lidar_range_noise_m, "Gaussian range noise (m), 0 = exact points");
  b.Field("origin_latitude_deg", &o.origin_latitude_deg, "latitude of the first frame (OXTS, deg)");
  b.Field("origin_longitude_deg", &o.origin_longitude_deg, "longitude of the first frame (OXTS, deg)");
  b.Field("origin_altitude_m", &o.origin_altitude_m, "altitude of the first frame (OXTS, m)");
  b.Field("origin_heading_deg", &o.origin_heading_deg, "heading of the first street, deg counter-clockwise from east");
}

void Bind(FieldBinder& b, LcmOptions& o) {
  b.Field("enabled", &o.enabled, "publish meshes, frame stats and poses over LCM (semap run --lcm-url sets it)");
  b.Field("url", &o.url, "LCM provider URL; ttl=0 keeps multicast on this host");
  b.Field("channel_prefix", &o.channel_prefix,
          "channel prefix: <prefix>MESH_SNAPSHOT, MESH_DELTA, FRAME_STATS, CAMERA_POSE");
  b.Field("snapshot_every", &o.snapshot_every,
          "full mesh snapshot every N mesh messages for late subscribers (0 = first only; N > 0 keeps the whole "
          "published mesh in memory)");
  b.Field("queue_capacity", &o.queue_capacity, "stats/pose messages queued at most; more are dropped and counted");
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
  s.push_back(MakeSection("synth", "Synthetic KITTI-format sequences (`semap synth`).", c.synth));
  s.push_back(MakeSection("lcm", "LCM publishing (non-blocking, own thread).", c.lcm));
  return s;
}

}  // namespace semap::io
