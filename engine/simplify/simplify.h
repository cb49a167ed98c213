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
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"

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
// Parses a name (exact, case-sensitive as listed above); throws InvalidOption("method", ...) if unknown.
SimplifyMethod SimplifyMethodFromName(const std::string& name);
// True for the methods that use the class map (LS*, AS*, ACS*, PS).
bool IsSemanticMethod(SimplifyMethod method);

struct SimplifyOptions {
  SimplifyMethod method = SimplifyMethod::kProbabilistic;  // which simplification (see SimplifyMethod)

  // Regions rho_i.
  double region_radius_m = 0.3;  // radius of the spherical regions (R methods, PS, LSB/ASB/PSB)
  int region_k = 32;             // neighbours per region for the K methods (the centre included)
  int density_samples = 4096;    // regions per group whose densities estimate D̄ (LS/AS/ACS/PS); 0 = all
  int normal_k = 12;             // neighbours of the PCA tangent-plane normal (and GB's surface variation)

  // Conservation factor (LS / AS / ACS).
  double target_conservation = 0.4;  // c̄: share of points kept in a region of average density (paper 0.4/0.5)
  double adaptive_stretch = 1.0;     // w of AS/ACS's f(x) = 0.5 + w x / (2 (1 + w |x|)), x in units of D̄
  double min_conservation = 0.0;     // lower clamp of c (paper: 0; > 0 never empties a very dense region)

  // Probabilistic simplification (PS / PSB).
  int ps_region_divisor = 8;         // N_r = |points of the class group| / divisor (paper: 8)
  double ps_boundary_share = 0.1;    // i(p̃) = 1 (interior, P_I) when p̃ < this, else P_B (paper: 0.1)
  double ps_interior_sigma_m = 0.2;  // σ of P_I = 1 − exp(−|x − μ|² / (2 d̃ σ²)) on the class plane
  double ps_boundary_sigma_m = 0.1;  // σ of P_B = exp(−d² / (2 σ²)), d = distance to the SVM boundary
  double ps_svm_c = 10.0;            // soft-margin C of the linear SVM (coordinates in region radii)
  int ps_svm_max_samples = 256;      // training points per SVM at most (evenly strided over the region)

  // Class planes (RANSAC per target group).
  double ransac_threshold_m = 0.05;  // inlier distance to the plane
  int ransac_iterations = 200;       // hypotheses per group
  int ransac_max_points = 20000;     // inliers are counted on at most this many random points of the group

  // Baselines.
  double gb_flatness_threshold = 0.01;     // GB: surface variation λ0/(λ0+λ1+λ2) below this is "flat"
  double gb_flat_keep_probability = 0.4;   // GB: a flat point is kept with this probability; others always
  double voxel_size_m = 0.1;               // voxel: edge of the grid cells
  int hierarchy_cluster_size = 10;         // hierarchy: CGAL size (max points per cluster)
  double hierarchy_max_variation = 0.333;  // hierarchy: CGAL maximum_variation (surface variation bound)

  // Streaming (WindowedSimplifier).
  int window_frames = 5;  // W: frames whose decided points give densities, planes and neighbourhoods

  std::uint64_t seed = 42;  // seed of the std::mt19937_64 behind every random choice

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
