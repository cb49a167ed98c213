// Accuracy and completeness in the usual multi-view-stereo sense, against an exact scene mesh (generated
// sequences): with a distance threshold τ,
// - accuracy     = share of the reconstruction's AREA within τ of the true surface, and the mean distance by
//                  area: points are sampled uniformly on the reconstruction's surface (stratified by area,
//                  SurfaceMetricsOptions::area_samples of them, a fixed seed), so a 200 m² triangle spanning
//                  a street weighs 20,000 times a 1 dm² one. Also the shares within / beyond near_m (0.5 m)
//                  and beyond far_m (2 m), and the total area;
// - vertex accuracy (the former figure, kept under this name) = share of the reconstruction's vertices and
//                  triangle centroids within τ: every triangle counts once whatever its size, so it cannot
//                  see large wrong triangles;
// - completeness = share of the true surface's samples within τ of the reconstruction, and their mean
//                  distance. The caller gives the true samples: only the observed part of the scene should
//                  count (io/eval uses the exact depth maps back-projected to the world).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/mesh.h"

namespace semap {

struct SurfaceMetricsOptions {
  // τ, the distance below which a sample counts as right (m).
  double threshold_m = 0.2;
  // The two further distance bins of the by-area figures (m): share within / beyond near_m, share beyond
  // far_m.
  double near_m = 0.5;
  double far_m = 2.0;
  // Points sampled on the reconstruction's surface for the by-area figures, whatever its area: the shares'
  // standard sampling error is at most 0.5 / sqrt(area_samples) (0.16 % at 100,000), less with
  // stratification.
  int area_samples = 100000;
  // Seed of the area samples: same mesh, same seed, same figures.
  std::uint64_t seed = 1;
  // Completeness by depth (when the truth samples' depths are given): the depths (m, increasing) between the
  // bands [0, e0), [e0, e1), …, [e_last, ∞). Stereo depth noise grows with the depth squared (at KITTI's f·B,
  // σ_z ≈ 0.2 m at 15 m, 1.2 m at 30 m for 0.5 px), so what τ = 0.2 m can reach depends on it.
  std::vector<double> completeness_depth_edges_m = {10.0, 20.0, 30.0};
  void Check() const;
};

struct SurfaceMetrics {
  double threshold_m = 0.0, near_m = 0.0, far_m = 0.0;  // the options' distances the figures use
  // By area (uniform samples on the reconstruction's surface).
  double area_m2 = 0.0;           // total area of the reconstruction's triangles
  double accuracy = 0.0;          // share of the area within τ of the truth (the headline accuracy)
  double area_within_near = 0.0;  // share of the area within near_m
  double area_beyond_near = 0.0;  // share of the area farther than near_m (= 1 − area_within_near)
  double area_beyond_far = 0.0;   // share of the area farther than far_m
  double mean_distance_m = 0.0;   // mean distance to the truth, by area
  std::int64_t area_samples = 0;  // 0 when the reconstruction has no area
  // Per vertex and triangle centroid (one sample each, whatever the triangle's size).
  double vertex_accuracy = 0.0;  // share of those samples within τ of the truth
  double vertex_mean_distance_m = 0.0;
  std::int64_t vertex_samples = 0;
  // Completeness.
  double completeness = 0.0;  // share of truth samples within τ of the reconstruction
  double mean_completeness_m = 0.0;
  std::int64_t truth_samples = 0;
  // Completeness of the truth samples seen at depths in [from_m, to_m) (to_m infinite for the last band);
  // empty unless their depths are given.
  struct DepthBand {
    double from_m = 0.0, to_m = 0.0;
    std::int64_t samples = 0;
    double completeness = 0.0;  // 0 for a band without samples
  };
  std::vector<DepthBand> completeness_by_depth;
};

// Distance from points to a fixed surface, by an AABB tree of its triangles (exact point–triangle distances;
// degenerate triangles are left out). Const queries are thread-safe.
class SurfaceDistance {
 public:
  // Requires at least one non-degenerate triangle (programmer error otherwise).
  explicit SurfaceDistance(const Mesh& surface);
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;
  double operator()(const Eigen::Vector3d& p) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// Points uniformly distributed by area on `mesh`'s triangles, stratified: sample k lies in the triangle that
// holds cumulative area (k + u_k) · A / count (u_k uniform in [0, 1)), at a uniform point of it.
// Deterministic for a seed. Empty when the mesh has no area.
std::vector<Eigen::Vector3d> SampleSurface(const Mesh& mesh, int count, std::uint64_t seed);

// Total area of `mesh`'s triangles (m²).
double SurfaceArea(const Mesh& mesh);

// An empty reconstruction has accuracy and completeness 0; an empty truth mesh is a programmer error.
// `truth_sample_depths_m`, empty or one per truth sample (the camera-frame depth it was seen at), gives
// completeness_by_depth. Thread-safe (no shared state).
SurfaceMetrics CompareSurfaces(const Mesh& reconstruction, const Mesh& truth,
                               const std::vector<Eigen::Vector3d>& truth_samples,
                               const SurfaceMetricsOptions& options = {},
                               const std::vector<double>& truth_sample_depths_m = {});

}  // namespace semap
