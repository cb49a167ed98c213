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
  s.push_back(MakeSection("lcm", "LCM publishing (non-blocking, own thread).", c.lcm));
  s.push_back(MakeSection("simplify", "Semantic simplification of ground and walls (paper Sec. III) and baselines.",
                          c.simplify));
  return s;
}

}  // namespace semap::io
