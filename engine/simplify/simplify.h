// Semantic point-cloud simplification (paper, Section "Point Cloud Semantic Simplification"): the region-wise
// methods LS / AS / ACS (radius R or KNN K regions), the probabilistic method PS, and the non-semantic
// baselines (LSB, ASB, PSB, GB, voxel grid, CGAL hierarchy clustering).
//
// Input: a LabelledCloud (positions, labels, observing camera centres) and a ClassMap (roles). Classes with
// role ground or wall are the targets: each role is one class *group* with its own RANSAC plane; every other
// class is returned bit-identical (its points are always kept). The baselines ignore semantics and treat the
// whole cloud as one group.
//
// Determinism: every random choice comes from one std::mt19937_64 seeded from SimplifyOptions::seed; the
// parallel parts (normals, region statistics) only compute per-point values, so the result does not depend
// on the number of threads or their order.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"
#include "engine/core/options.h"

namespace semap {

enum class SimplifyMethod : std::uint8_t {
  kOriginal,               // O: no simplification
  kGeometricBaseline,      // GB: curvature (surface variation) baseline, no semantics
  kLinearBaseline,         // LSB: LS with the whole cloud as one class (radius regions)
  kAdaptiveBaseline,       // ASB: AS with the whole cloud as one class (radius regions)
  kProbabilisticBaseline,  // PSB: PS with the whole cloud as one class, without P_B
  kLinearRadius,           // LSR
  kLinearKnn,              // LSK
  kAdaptiveRadius,         // ASR
  kAdaptiveKnn,            // ASK
  kAdaptiveClassRadius,    // ACSR
  kAdaptiveClassKnn,       // ACSK
  kProbabilistic,          // PS
  kVoxel,                  // voxel: one point per voxel (the one nearest the voxel's centroid), no semantics
  kHierarchy,              // hierarchy: CGAL::hierarchy_simplify_point_set, no semantics
};

// The method's short name as used in configs and on the command line ("PS", "ACSR", "voxel", ...).
const char* SimplifyMethodName(SimplifyMethod method);
// Every method in declaration order.
const std::vector<SimplifyMethod>& AllSimplifyMethods();
// Parses a name (exact, case-sensitive as listed above); throws InvalidOption naming simplify's method key if
// unknown.
SimplifyMethod SimplifyMethodFromName(const std::string& name);
// True for the methods that use the class map (LS*, AS*, ACS*, PS).
bool IsSemanticMethod(SimplifyMethod method);

struct SimplifyOptions {
  // Each field's key and meaning: Describe() below, once (what `semap config --defaults` prints).
  SimplifyMethod method = SimplifyMethod::kProbabilistic;

  // Regions rho_i.
  double region_radius_m = 0.3;
  int region_k = 32;
  int density_samples = 4096;
  int normal_k = 12;

  // Conservation factor (LS / AS / ACS).
  double target_conservation = 0.4;  // paper: 0.4 / 0.5
  double adaptive_stretch = 1.0;
  double min_conservation = 0.0;  // paper: 0

  // Probabilistic simplification (PS / PSB).
  int ps_region_divisor = 8;       // paper: 8
  double ps_boundary_share = 0.1;  // paper: 0.1
  double ps_interior_sigma_m = 0.2;
  double ps_boundary_sigma_m = 0.1;
  double ps_svm_c = 10.0;
  int ps_svm_max_samples = 256;

  // Class planes (RANSAC per target group).
  double ransac_threshold_m = 0.05;
  int ransac_iterations = 200;
  int ransac_max_points = 2000;
  double ransac_confidence = 0.999;

  // Baselines.
  double gb_flatness_threshold = 0.01;
  double gb_flat_keep_probability = 0.4;
  double voxel_size_m = 0.1;
  int hierarchy_cluster_size = 10;
  double hierarchy_max_variation = 0.333;

  // Streaming (WindowedSimplifier).
  int window_frames = 5;

  std::uint64_t seed = 42;

  // Each field's config key, text and valid values, declared once here (engine/core/options.h): app/config
  // binds them to YAML, `semap config --defaults` prints them and Check() tests the values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    // The largest surface variation λ0/(λ0+λ1+λ2) there is (three equal eigenvalues).
    const Bound kOneThird(1.0 / 3.0, "1/3");
    std::vector<std::pair<std::string, SimplifyMethod>> methods;
    for (auto m : AllSimplifyMethods()) methods.emplace_back(SimplifyMethodName(m), m);
    v.Enum("method", &method, methods,
           "O = none; LSR/LSK, ASR/ASK, ACSR/ACSK = linear / adaptive / adaptive-class with radius / KNN "
           "regions; PS = probabilistic; baselines without semantics: LSB, ASB, PSB, GB (curvature), voxel, "
           "hierarchy (CGAL)");
    v.Field("region_radius_m", &region_radius_m,
            "radius of the spherical regions (R methods, PS, LSB/ASB/PSB)", Above(0));
    v.Field("region_k", &region_k, "neighbours per region of the K methods (the centre included)",
            AtLeast(3));
    v.Field("density_samples", &density_samples,
            "regions per class group whose densities estimate the mean density D̄ (LS/AS/ACS/PS); 0 = all",
            AtLeast(0));
    v.Field("normal_k", &normal_k,
            "neighbours of the PCA tangent-plane normals (ranking r) and of GB's surface variation",
            AtLeast(3));
    v.Field("target_conservation", &target_conservation,
            "c̄: share of points kept in a region of average density (paper: 0.4 / 0.5)", Above(0).Below(1));
    v.Field("adaptive_stretch", &adaptive_stretch,
            "w of AS/ACS's f(x) = 0.5 + w x / (2 (1 + w |x|)), x in units of D̄", Above(0));
    v.Field(
        "min_conservation", &min_conservation,
        "lower clamp of c (paper: 0; above 0 never empties a very dense region); at most target_conservation",
        AtLeast(0));
    v.Field("ps_region_divisor", &ps_region_divisor,
            "PS: N_r = |points of the class group| / divisor (paper: 8)", AtLeast(1));
    v.Field("ps_boundary_share", &ps_boundary_share,
            "PS: regions with a share of other labels p̃ below this are interior and use P_I, others P_B "
            "(paper: 0.1)",
            Above(0).AtMost(1));
    v.Field("ps_interior_sigma_m", &ps_interior_sigma_m,
            "PS: σ of P_I = 1 − exp(−|x − μ|² / (2 d̃ σ²)) on the class plane", Above(0));
    v.Field("ps_boundary_sigma_m", &ps_boundary_sigma_m,
            "PS: σ of P_B = exp(−d² / (2 σ²)), d to the SVM boundary", Above(0));
    v.Field("ps_svm_c", &ps_svm_c, "PS: soft-margin C of the linear SVM (coordinates in region radii)",
            Above(0));
    v.Field("ps_svm_max_samples", &ps_svm_max_samples,
            "PS: training points per SVM at most (evenly strided over the region)", AtLeast(2));
    v.Field("ransac_threshold_m", &ransac_threshold_m, "class planes: RANSAC inlier distance to the plane",
            Above(0));
    v.Field("ransac_iterations", &ransac_iterations,
            "class planes: RANSAC hypotheses per class group, at most", AtLeast(1));
    v.Field("ransac_max_points", &ransac_max_points,
            "class planes: hypotheses scored on at most this many random points of the group (the best is "
            "then refitted to its inliers among all the group's points)",
            AtLeast(3));
    v.Field("ransac_confidence", &ransac_confidence,
            "class planes: RANSAC stops once an all-inlier draw was this likely given the best inlier share "
            "so far (1 = always ransac_iterations)",
            Above(0).AtMost(1));
    v.Field("gb_flatness_threshold", &gb_flatness_threshold,
            "GB: surface variation λ0/(λ0+λ1+λ2) below this is flat", In(0, kOneThird));
    v.Field("gb_flat_keep_probability", &gb_flat_keep_probability,
            "GB: probability of keeping a flat point (others are always kept)", In(0, 1));
    v.Field("voxel_size_m", &voxel_size_m, "voxel: grid cell edge", Above(0));
    v.Field("hierarchy_cluster_size", &hierarchy_cluster_size, "hierarchy: CGAL maximum cluster size",
            AtLeast(1));
    v.Field("hierarchy_max_variation", &hierarchy_max_variation, "hierarchy: CGAL maximum surface variation",
            Above(0).AtMost(kOneThird));
    v.Field("window_frames", &window_frames,
            "streaming: frames whose kept points stay in the window and give densities, planes and "
            "neighbourhoods (should cover the frames that overlap)",
            AtLeast(1));
    v.Field("seed", &seed,
            "seed of the random generator behind every random choice (same seed, same output)");
  }

  void Check() const;
};

// What happened to one label's points.
struct ClassSimplifyStats {
  Label label = 0;
  std::uint64_t in = 0;  // points of this label given to the simplifier
  std::uint64_t kept = 0;
  std::uint64_t removed = 0;  // in − kept
};

struct SimplifyResult {
  std::vector<std::uint32_t> kept_indices;    // ascending indices into the input cloud
  std::vector<ClassSimplifyStats> per_class;  // one entry per label present, ascending label
  double time_s = 0.0;                        // wall time of the simplification
  std::uint64_t in = 0;
  std::uint64_t kept() const { return kept_indices.size(); }
};

// Simplifies `cloud` (labels absent = every point unlabelled). Thread-safe (no shared state).
// Requires options.Check() to pass (asserted via Check(), which throws InvalidOption).
SimplifyResult Simplify(const LabelledCloud& cloud, const ClassMap& class_map,
                        const SimplifyOptions& options);

// The kept subset of `cloud` (every attribute carried, cameras unchanged).
LabelledCloud ApplySimplification(const LabelledCloud& cloud, const SimplifyResult& result);

}  // namespace semap
