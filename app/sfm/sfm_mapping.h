// A reconstruction through the Delaunay map (engine/map): in one go (BuildBatchMap), or view by view as
// keyframes (IncrementalMap), with optional semantic simplification of labelled points (engine/simplify).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/core/labelled_cloud.h"
#include "engine/core/mesh.h"
#include "engine/core/mesh_delta.h"
#include "engine/map/incremental_map.h"
#include "engine/map/map_options.h"
#include "engine/map/map_types.h"
#include "engine/pipeline/frame_stats.h"
#include "engine/simplify/simplify.h"
#include "engine/simplify/windowed_simplifier.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::app {

// The batch map's input: every observed point with its first observing view (in view order) as its camera
// and its other observations as extra rays (a view observing a point twice gives one ray); camera i is view
// i (frame id i). Colours and labels carried.
struct SfmBatchInput {
  LabelledCloud cloud;
  std::vector<Observation> extra;
  std::vector<std::uint32_t> point_index;  // cloud point → reconstruction point
  std::size_t unobserved_points = 0;       // points no view observes: left out
};
SfmBatchInput MakeBatchInput(const io::SfmReconstruction& reconstruction);

// View `view` as a keyframe: the points it observes first (no earlier view does) and the points it observes
// again. Both ascending, without repeats.
struct SfmKeyframe {
  std::uint32_t view = 0;
  std::vector<std::uint32_t> new_points;
  std::vector<std::uint32_t> seen_points;
};
// One keyframe per view, in view order.
std::vector<SfmKeyframe> MakeKeyframes(const io::SfmReconstruction& reconstruction);
// The keyframe's new points as map input: camera 0 is the view's centre (frame id = view index).
LabelledCloud KeyframeCloud(const io::SfmReconstruction& reconstruction, const SfmKeyframe& keyframe);

// The largest |coordinate| a reconstruction may have for the map of `map`: the map covers a bounded region
// around the origin (its Steiner lattice holds about ±10^6 cubes of map.steiner_spacing_m). Beyond 1000 km,
// or beyond 10^5 cubes, a coordinate is an outlier of the reconstruction or a unit mistake, never a street,
// and must not reach the map's range assertion.
double MaxSfmCoordinateM(const MapOptions& map);

// The points left out by DropFarPoints: how many, and the file id of the first.
struct FarPoints {
  std::size_t count = 0;
  std::int64_t first_id = 0;
};
// Leaves out the points with a coordinate beyond `limit_m` (or not finite), with their observations. A view
// whose centre is beyond is an error: throws io::FileError naming `input` and the view.
FarPoints DropFarPoints(const std::filesystem::path& input, double limit_m,
                        io::SfmReconstruction* reconstruction);

// Simplification applies when the method is not O and the reconstruction has labels.
bool SimplifiesSfm(const io::SfmReconstruction& reconstruction, const SimplifyOptions& simplify);

struct SfmBatchResult {
  Mesh mesh;
  MapStatistics statistics;
  std::size_t points_in = 0;    // observed points
  std::size_t points_kept = 0;  // after simplification
  std::size_t rays = 0;         // first rays + extra rays given to the map
  std::size_t unobserved_points = 0;
  double simplify_s = 0.0;
  double map_s = 0.0;
};
// Throws InvalidOption for bad options.
SfmBatchResult MapSfmBatch(const io::SfmReconstruction& reconstruction, const MapOptions& map,
                           const SimplifyOptions& simplify, const ClassMap& class_map);

struct SfmKeyframeResult {
  std::uint32_t view = 0;
  std::size_t new_points = 0;            // first observed by this view
  std::size_t kept_points = 0;           // after simplification (= new_points without it)
  std::size_t observations = 0;          // extra rays to points already in the map
  std::size_t observations_skipped = 0;  // of points simplified away, dropped by the map or finalised
  std::size_t inserted = 0, merged = 0, dropped = 0, finalised = 0;  // MapUpdateResult counters
  std::vector<ClassPointCount> class_counts;  // simplification per class (empty without it)
  double simplify_s = 0.0;
  double map_s = 0.0;   // IncrementalMap::Update
  double live_s = 0.0;  // after an update that finalised points: which points are still live (a snapshot)
  double mesh_s = 0.0;  // surface extraction and mesh delta
  MeshDelta delta;      // change of the published mesh (finalised parts are added once, never removed)
  MapStatistics statistics;
  std::int64_t mesh_triangles = 0;  // triangles of the mesh as published so far
};

// Feeds the views of a reconstruction to an IncrementalMap in order, one keyframe per Step(): the points a
// view observes first (simplified when SimplifiesSfm) with the view's centre as their camera, plus one
// extra ray from the view to each point it observes again that the map still holds. Observations of points
// the map merged are rays to the point they were merged into; observations of points simplified away,
// dropped (beyond max_ray_length_m) or finalised are skipped and counted. Not thread-safe. `reconstruction`
// must outlive the mapper.
class SfmIncrementalMapper {
 public:
  // Throws InvalidOption for bad options.
  SfmIncrementalMapper(const io::SfmReconstruction& reconstruction, const MapOptions& map,
                       const SimplifyOptions& simplify, ClassMap class_map);

  std::size_t num_keyframes() const { return keyframes_.size(); }
  bool done() const { return next_ >= keyframes_.size(); }
  // The next keyframe (requires !done()).
  SfmKeyframeResult Step();
  // After the last keyframe: the delta that completes the mesh.
  MeshDelta Finish();
  const IncrementalMap& map() const { return map_; }

 private:
  void RefreshLivePoints();

  const io::SfmReconstruction* reconstruction_;
  std::vector<SfmKeyframe> keyframes_;
  std::size_t next_ = 0;
  IncrementalMap map_;
  MeshDiffer differ_;
  std::int64_t published_triangles_ = 0;
  bool simplify_ = false;
  std::unique_ptr<WindowedSimplifier> simplifier_;
  std::vector<std::uint32_t> map_id_;         // per reconstruction point: map point id, or a kNo* marker
  std::vector<std::uint32_t> mapped_points_;  // reconstruction points with a live map id (pruned lazily)
};

}  // namespace semap::app
