// Binds every stage's options struct to its config section. One Bind() per options struct;
// the doc strings here are what config/default.yaml shows.
#include "engine/core/check.h"
#include "app/config/config.h"

namespace semap::app {

using namespace io;  // the options structs of io/ and the field binder

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
  b.Field("loops", &o.loops,
          "read the frames this many times (soak runs); each pass is shifted past the previous one's track");
  b.Field("loop_gap_m", &o.loop_gap_m,
          "gap between the camera tracks of consecutive passes, m (keep above 2 x depth.max_depth_m)");
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

void Bind(FieldBinder& b, PipelineOptions& o) {
  using M = PipelineOptions::Mode;
  using E = PipelineOptions::OnError;
  b.Enum("mode", &o.mode, {{"exhaustive", M::kExhaustive}, {"realtime", M::kRealtime}},
         "exhaustive: every frame processed (the paper's table); realtime: read at sensor rate, drop when behind");
  b.Field("realtime_rate_hz", &o.realtime_rate_hz, "realtime mode: frame rate when the sequence has no timestamps");
  b.Field("depth_workers", &o.depth_workers, "threads running SGBM depth (frames are reordered after them)");
  b.Field("queue_capacity", &o.queue_capacity, "frames each queue between stages holds at most");
  b.Enum("on_error", &o.on_error, {{"skip", E::kSkipFrame}, {"stop", E::kStop}},
         "a stage failing on a frame: skip the frame (counted) or stop the run (drain, write the mesh)");
  b.Field("max_speed_mps", &o.max_speed_mps,
          "skip (and count) a frame whose camera moved faster than this since the last accepted frame, m/s "
          "(a pose jump); 0 = no check");
  b.Field("cpu_affinity", &o.cpu_affinity, "CPU ids the engine's threads may run on, e.g. [0, 1]; [] = any");
  b.Field("mesh_every_frames", &o.mesh_every_frames,
          "the map extracts and publishes the mesh's change every this many frames (and at the end), "
          "integrating every frame; 1 = every frame; the final mesh is the same for any value");
}

void Bind(FieldBinder& b, OutputOptions& o) {
  b.Field("dir", &o.dir, "output folder (mesh.ply, mesh.off, frames.csv, frames.jsonl, summary.json)");
  b.Field("mesh_ply", &o.mesh_ply, "write the final mesh as PLY with colour and label");
  b.Field("mesh_off", &o.mesh_off, "write the final mesh as ASCII OFF (the paper's size measure)");
  b.Field("ply_ascii", &o.ply_ascii, "ASCII PLY instead of binary little-endian");
  b.Field("frame_stats", &o.frame_stats, "per-frame statistics as frames.csv and frames.jsonl");
}

void Bind(FieldBinder& b, LcmOptions& o) {
  b.Field("enabled", &o.enabled, "publish meshes, frame stats and poses over LCM (semap run --lcm-url sets it)");
  b.Field("url", &o.url, "LCM provider URL; ttl=0 keeps multicast on this host");
  b.Field("channel_prefix", &o.channel_prefix,
          "channel prefix: <prefix>MESH_BLOCK, MESH_END, FRAME_STATS, CAMERA_POSE");
  b.Field("block_size_m", &o.block_size_m,
          "edge of the cubic cells that cut the mesh into blocks (a triangle goes to its centroid's cell)");
  b.Field("max_message_bytes", &o.max_message_bytes,
          "bound on every mesh message; larger blocks go in parts (<= ~65000: one UDP datagram each)");
  b.Field("resend_bytes_per_s", &o.resend_bytes_per_s,
          "budget of the round-robin re-send of block states and of the closing rounds (late subscribers "
          "converge in about mesh bytes / budget)");
  b.Field("max_bytes_per_s", &o.max_bytes_per_s,
          "ceiling on all mesh traffic: messages are spaced so that a subscriber's socket buffer keeps up; "
          "changes published meanwhile are coalesced");
  b.Field("closing_rounds", &o.closing_rounds,
          "re-send rounds over every block at the end of the run, before its last message");
  b.Field("closing_max_s", &o.closing_max_s, "at most this long for the closing rounds");
  b.Field("queue_capacity", &o.queue_capacity, "stats/pose messages queued at most; more are dropped and counted");
}

void Bind(FieldBinder& b, DepthOptions& o) {
  b.Field("num_disparities", &o.num_disparities, "disparity search range in px at full resolution (multiple of 16)");
  b.Field("block_size", &o.block_size, "SGBM matched block size in px (odd, 1..11)");
  b.Field("p1", &o.p1, "SGBM penalty for 1 px disparity changes; 0 = 8*channels*block_size^2");
  b.Field("p2", &o.p2, "SGBM penalty for larger disparity changes; 0 = 32*channels*block_size^2");
  b.Field("uniqueness_ratio", &o.uniqueness_ratio, "margin in % of the best cost over the second best");
  b.Field("speckle_window_size", &o.speckle_window_size,
          "speckle filter: largest region in px invalidated (0 = off)");
  b.Field("speckle_range_px", &o.speckle_range_px, "speckle filter: disparity variation within a region");
  b.Field("disp12_max_diff_px", &o.disp12_max_diff_px,
          "left-right consistency check: max left/right disparity difference in px (-1 = off)");
  b.Field("left_right_max_diff_px", &o.left_right_max_diff_px,
          "explicit left-right check with a second matching pass: max difference in px (-1 = off)");
  b.Field("pre_filter_cap", &o.pre_filter_cap, "SGBM x-derivative prefilter truncation (0 = OpenCV default)");
  b.Enum("mode", &o.mode,
         {{"sgbm", SgbmMode::kSgbm}, {"hh", SgbmMode::kHh}, {"3way", SgbmMode::kThreeWay}, {"hh4", SgbmMode::kHh4}},
         "OpenCV SGBM mode");
  b.Field("half_resolution", &o.half_resolution, "match at half resolution (about 4x faster; doubles pixel_stride)");
  b.Field("fill_max_gap_px", &o.fill_max_gap_px,
          "fill horizontal gaps up to this many px with the background disparity (0 = off)");
  b.Field("fill_left_border", &o.fill_left_border,
          "extend each row's first valid disparity over the unmatched left band (confidence 0)");
  b.Field("filled_confidence", &o.filled_confidence, "confidence of gap-filled pixels (matched = 1)");
  b.Field("min_depth_m", &o.min_depth_m, "nearest point kept (camera-frame z, m)");
  b.Field("max_depth_m", &o.max_depth_m, "farthest point kept (camera-frame z, m)");
  b.Field("pixel_stride", &o.pixel_stride, "one point every pixel_stride px on every pixel_stride-th row");
  b.Field("max_points_per_frame", &o.max_points_per_frame, "point budget per frame after the stride (0 = none)");
  b.Field("min_point_confidence", &o.min_point_confidence, "pixels below this confidence give no point");
  b.Field("vote_stride_px", &o.vote_stride_px,
          "the map's visibility votes read one pixel in vote_stride_px on every vote_stride_px-th row of the "
          "depth map (map.visibility: depth); every valid one votes, whatever max_points_per_frame");
}

void Bind(FieldBinder& b, SemanticsOptions& o) {
  b.Enum("source", &o.source,
         {{"auto", LabelSource::kAuto}, {"disk", LabelSource::kDisk}, {"enet", LabelSource::kEnet},
          {"none", LabelSource::kNone}},
         "label source: auto = label images from disk when present else unlabelled, enet = built-in segmenter");
  b.Field("enet_model_path", &o.enet_model_path, "ENet Cityscapes Torch7 model file");
  b.Field("enet_input_width_px", &o.enet_input_width_px, "ENet input width in px (multiple of 8)");
  b.Field("enet_input_height_px", &o.enet_input_height_px, "ENet input height in px (multiple of 8)");
  b.Field("enet_keep_aspect", &o.enet_keep_aspect,
          "keep the image's aspect ratio in the network input (pad) instead of stretching it");
  b.Field("enet_threads", &o.enet_threads, "OpenCV threads for ENet (process-wide; 0 = unchanged)");
  b.Field("enet_every_frames", &o.enet_every_frames,
          "semap run: ENet on its own thread on keyframes only, every enet_every_frames frames (1 = every frame, in "
          "the depth workers)");
  b.Enum("enet_propagation", &o.enet_propagation,
         {{"reproject", LabelPropagation::kReproject}, {"reuse", LabelPropagation::kReuse}},
         "labels of frames between keyframes: reproject the keyframe's (frame depth + relative pose) or reuse them");
  b.Enum("size_mismatch", &o.size_mismatch,
         {{"resize", LabelSizePolicy::kResizeNearest}, {"refuse", LabelSizePolicy::kRefuse}},
         "label image of another size than the image: resize with nearest neighbour (warned) or refuse");
  b.Field("drop_sky", &o.drop_sky, "pixels labelled sky (the class map's class named sky) give no point");
}

void Bind(FieldBinder& b, SimplifyOptions& o) {
  std::vector<std::pair<std::string, SimplifyMethod>> methods;
  for (auto m : AllSimplifyMethods()) methods.emplace_back(SimplifyMethodName(m), m);
  b.Enum("method", &o.method, methods,
         "O = none; LSR/LSK, ASR/ASK, ACSR/ACSK = linear / adaptive / adaptive-class with radius / KNN regions; "
         "PS = probabilistic; baselines without semantics: LSB, ASB, PSB, GB (curvature), voxel, hierarchy (CGAL)");
  b.Field("region_radius_m", &o.region_radius_m, "radius of the spherical regions (R methods, PS, LSB/ASB/PSB)");
  b.Field("region_k", &o.region_k, "neighbours per region of the K methods");
  b.Field("density_samples", &o.density_samples,
          "regions per class group whose densities estimate the mean density D̄ (LS/AS/ACS/PS); 0 = all");
  b.Field("normal_k", &o.normal_k, "neighbours of the PCA normals (ranking r) and of GB's surface variation");
  b.Field("target_conservation", &o.target_conservation,
          "c̄: share of points kept in a region of average density (paper: 0.4 / 0.5)");
  b.Field("adaptive_stretch", &o.adaptive_stretch, "w of AS/ACS's f(x) = 0.5 + w x / (2 (1 + w |x|)), x in units of D̄");
  b.Field("min_conservation", &o.min_conservation, "lower clamp of c (paper: 0)");
  b.Field("ps_region_divisor", &o.ps_region_divisor, "PS: N_r = |points of the class group| / divisor (paper: 8)");
  b.Field("ps_boundary_share", &o.ps_boundary_share,
          "PS: regions with a share of other labels p̃ below this use P_I, others P_B (paper: 0.1)");
  b.Field("ps_interior_sigma_m", &o.ps_interior_sigma_m, "PS: σ of P_I = 1 − exp(−|x − μ|² / (2 d̃ σ²))");
  b.Field("ps_boundary_sigma_m", &o.ps_boundary_sigma_m, "PS: σ of P_B = exp(−d² / (2 σ²)), d to the SVM boundary");
  b.Field("ps_svm_c", &o.ps_svm_c, "PS: soft-margin C of the linear SVM (coordinates in region radii)");
  b.Field("ps_svm_max_samples", &o.ps_svm_max_samples, "PS: training points per SVM at most (strided)");
  b.Field("ransac_threshold_m", &o.ransac_threshold_m, "class planes: RANSAC inlier distance");
  b.Field("ransac_iterations", &o.ransac_iterations, "class planes: RANSAC hypotheses per class group");
  b.Field("ransac_max_points", &o.ransac_max_points, "class planes: inliers counted on at most this many points");
  b.Field("gb_flatness_threshold", &o.gb_flatness_threshold, "GB: surface variation below this is flat");
  b.Field("gb_flat_keep_probability", &o.gb_flat_keep_probability, "GB: probability of keeping a flat point");
  b.Field("voxel_size_m", &o.voxel_size_m, "voxel: grid cell edge");
  b.Field("hierarchy_cluster_size", &o.hierarchy_cluster_size, "hierarchy: CGAL maximum cluster size");
  b.Field("hierarchy_max_variation", &o.hierarchy_max_variation, "hierarchy: CGAL maximum surface variation");
  b.Field("window_frames", &o.window_frames,
          "streaming: frames whose kept points stay in the window (should cover the frames that overlap)");
  b.Field("seed", &o.seed, "seed of the random generator (same seed, same output)");
}

void Bind(FieldBinder& b, DepthAccuracyOptions& o) {
  b.Field("min_depth_m", &o.min_depth_m, "reference depths (camera-frame z, not range) nearer than this are ignored");
  b.Field("max_depth_m", &o.max_depth_m, "reference depths farther than this are ignored");
  b.Field("max_abs_error_m", &o.max_abs_error_m,
          "errors above this are left out of RMSE/MAE (still count as covered); 0 = keep all");
  b.Field("surface_threshold_m", &o.surface_threshold_m,
          "generated sequences: distance τ of accuracy / completeness against the exact scene mesh");
  b.Field("surface_pixel_stride", &o.surface_pixel_stride,
          "generated sequences: exact depth maps sampled every this many pixels give the observed true surface");
  b.Field("surface_area_samples", &o.surface_area_samples,
          "generated sequences: points sampled uniformly by area on the mesh for the by-area accuracy (fixed seed)");
}

void Bind(FieldBinder& b, MapOptions& o) {
  b.Enum("visibility", &o.visibility, {{"depth", Visibility::kDepth}, {"rays", Visibility::kRays}},
         "where the visibility votes come from: depth (each frame's depth map, every valid pixel a ray; "
         "cells sampled against it) | rays (one exact walk per point ray, the paper's votes; also for SfM input)");
  b.Field("vote_window_frames", &o.vote_window_frames,
          "depth: the views of this many last frames vote the cells an insertion creates");
  b.Field("merge_radius_px", &o.merge_radius_px,
          "depth: a new point projecting within this many px of a live vertex (and within merge_depth_fraction "
          "of its depth) adds to that vertex's support instead of becoming a vertex");
  b.Field("merge_depth_fraction", &o.merge_depth_fraction, "depth: see merge_radius_px");
  b.Field("disparity_sigma_px", &o.disparity_sigma_px,
          "depth: σ of the stereo disparity, px; a pixel's depth z is uncertain by z²σ/(f·B): cells are voted "
          "free only before that band, matter within it (0 = exact points, the paper's votes)");
  b.Field("sigma_free_m", &o.sigma_free_m, "σ_free of the free-space weight 1 - exp(-d²/(2σ²)), metres");
  b.Field("sigma_matter_m", &o.sigma_matter_m, "σ_matter of the matter weight 1 - exp(-d²/(2σ²)), metres");
  b.Field("ray_extension_factor", &o.ray_extension_factor,
          "rays are extended behind their point by this many σ_matter (matter votes)");
  b.Field("max_ray_length_m", &o.max_ray_length_m,
          "points farther than this from their camera are dropped; 0 = no limit");
  b.Field("merge_distance_m", &o.merge_distance_m,
          "rays: a new point this close to an existing one is merged into it (only its ray is added); 0 = "
          "exact duplicates only");
  b.Enum("extraction", &o.extraction,
         {{"carve_and_repair", SurfaceExtraction::kCarveAndRepair},
          {"greedy_growth", SurfaceExtraction::kGreedyGrowth}},
         "manifold surface extraction: carve_and_repair (carve every free cell, repair the manifold "
         "locally, grow) | greedy_growth (the paper's region growing from the most free cell)");
  b.Field("grow_passes", &o.grow_passes,
          "region-growing passes retrying the cells the manifold test refused");
  b.Field("repair_fill_cost", &o.repair_fill_cost,
          "carve_and_repair: cost in ray weights of carving a non-free cell to make a vertex regular "
          "(besides its matter excess), against the free votes given up by uncarving instead");
  b.Field("steiner_spacing_m", &o.steiner_spacing_m, "spacing of the bounding Steiner lattice, metres");
  b.Field("steiner_margin_cubes", &o.steiner_margin_cubes, "lattice cubes kept around each point and camera");
  b.Field("drop_steiner_triangles", &o.drop_steiner_triangles,
          "leave triangles touching a Steiner vertex out of the mesh");
  b.Field("drop_unseen_surface", &o.drop_unseen_surface,
          "depth: leave out surface triangles no view saw as a surface (no lids over unseen space)");
  b.Field("seen_noise_sigmas", &o.seen_noise_sigmas,
          "depth: a triangle is seen as a surface within ray extension + this many depth σ of a pixel's depth");
  b.Field("fill_unseen_holes_facets", &o.fill_unseen_holes_facets,
          "depth: a hole of at most this many unseen triangles ringed by seen ones counts as seen; 0 = never");
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
  // In the order of the data flow.
  std::vector<Section> s;
  s.push_back(MakeSection("input", "Input: where frames come from and what is loaded with them.", c.input));
  s.push_back(MakeSection("depth", "Depth: stereo matching (OpenCV SGBM) and the per-frame point cloud.", c.depth));
  s.push_back(MakeSection("semantics", "Semantics: where the per-pixel labels come from (first-camera rule).",
                          c.semantics));
  s.push_back(MakeSection("simplify", "Semantic simplification of ground and walls (paper Sec. III) and baselines.",
                          c.simplify));
  s.push_back(MakeSection("map", "Delaunay map: visibility votes, manifold extraction, incremental update, memory bound.",
                          c.map));
  s.push_back(MakeSection("synth", "Synthetic KITTI-format sequences (`semap synth`).", c.synth));
  s.push_back(MakeSection("pipeline", "Streaming engine: threads, queues, real-time or exhaustive.", c.pipeline));
  s.push_back(MakeSection("output", "Files written by `semap run`.", c.output));
  s.push_back(MakeSection("lcm", "LCM publishing (non-blocking, own thread).", c.lcm));
  s.push_back(MakeSection("eval", "Accuracy of a mesh against Velodyne / exact depth (semap eval, table, compare).",
                          c.eval));
  return s;
}

}  // namespace semap::app
