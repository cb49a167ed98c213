// Accuracy and completeness in the usual multi-view-stereo sense, against an exact scene mesh (generated
// sequences): with a distance threshold τ,
// - accuracy     = share of the reconstruction's samples (its vertices and triangle centroids) within τ of
//                  the true surface, and their mean distance;
// - completeness = share of the true surface's samples within τ of the reconstruction, and their mean
//                  distance. The caller gives the true samples: only the observed part of the scene should count
//                  (io/eval uses the exact depth maps back-projected to the world).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/core/mesh.h"

namespace semap {

struct SurfaceMetricsOptions {
  // τ, the distance below which a sample counts as right (m).
  double threshold_m = 0.2;
  void Check() const;
};

struct SurfaceMetrics {
  double accuracy = 0.0;           // share of reconstruction samples within τ of the truth
  double mean_accuracy_m = 0.0;    // their mean distance to the truth
  double completeness = 0.0;       // share of truth samples within τ of the reconstruction
  double mean_completeness_m = 0.0;
  std::int64_t reconstruction_samples = 0;
  std::int64_t truth_samples = 0;
};

// Distances by an AABB tree of each mesh (exact point–triangle distances). An empty reconstruction has
// completeness 0; an empty truth mesh is a programmer error. Thread-safe (no shared state).
SurfaceMetrics CompareSurfaces(const Mesh& reconstruction, const Mesh& truth,
                               const std::vector<Eigen::Vector3d>& truth_samples,
                               const SurfaceMetricsOptions& options = {});

}  // namespace semap
