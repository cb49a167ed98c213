#include "app/sfm/sfm_mapping.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <chrono>
#include <unordered_set>

#include "engine/core/check.h"
#include "engine/map/batch_map.h"
#include "io/file_error.h"

namespace semap::app {

using namespace io;  // the reconstruction types of io/sfm

namespace {

constexpr double kMaxSfmCoordinateM = 1e6;
constexpr double kMaxLatticeCubes = 1e5;

bool Beyond(const Eigen::Vector3d& p, double limit_m) {
  return !p.allFinite() || p.cwiseAbs().maxCoeff() > limit_m;
}

}  // namespace

double MaxSfmCoordinateM(const MapOptions& map) {
  return std::min(kMaxSfmCoordinateM, kMaxLatticeCubes * map.steiner_spacing_m);
}

FarPoints DropFarPoints(const std::filesystem::path& input, double limit_m, SfmReconstruction* r) {
  for (const SfmView& v : r->views) {
    if (Beyond(v.world_from_cam.translation(), limit_m)) {
      throw FileError(input, fmt::format("view {} ({}) has its centre beyond {} m from the origin: not a "
                                         "reconstruction in metres?",
                                         v.id, v.name, limit_m));
    }
  }
  FarPoints far;
  std::vector<std::int64_t> new_index(r->num_points(), -1);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < r->num_points(); ++i) {
    if (Beyond(r->points_world[i], limit_m)) {
      if (far.count++ == 0) far.first_id = r->point_ids[i];
      continue;
    }
    new_index[i] = static_cast<std::int64_t>(kept);
    r->points_world[kept] = r->points_world[i];
    r->point_ids[kept] = r->point_ids[i];
    if (!r->point_colors_rgb.empty()) r->point_colors_rgb[kept] = r->point_colors_rgb[i];
    if (!r->point_labels.empty()) r->point_labels[kept] = r->point_labels[i];
    ++kept;
  }
  if (far.count == 0) return far;
  r->points_world.resize(kept);
  r->point_ids.resize(kept);
  if (!r->point_colors_rgb.empty()) r->point_colors_rgb.resize(kept);
  if (!r->point_labels.empty()) r->point_labels.resize(kept);
  std::vector<SfmObservation> observations;
  observations.reserve(r->observations.size());
  for (SfmObservation o : r->observations) {
    if (new_index[o.point] < 0) continue;
    o.point = static_cast<std::uint32_t>(new_index[o.point]);
    observations.push_back(o);
  }
  r->observations = std::move(observations);
  r->AssertConsistent();
  return far;
}
namespace {

// Markers of SfmIncrementalMapper::map_id_ besides a live map point id (kDroppedPoint: beyond range).
constexpr std::uint32_t kUnseen = 0xFFFFFFFEu;
constexpr std::uint32_t kSimplifiedAway = 0xFFFFFFFDu;
constexpr std::uint32_t kFinalised = 0xFFFFFFFCu;
constexpr std::uint32_t kFirstMarker = kFinalised;

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Index of each point's first observation (observations are sorted by point, then view), or SIZE_MAX.
std::vector<std::size_t> FirstObservation(const SfmReconstruction& r) {
  std::vector<std::size_t> first(r.num_points(), SIZE_MAX);
  for (std::size_t i = r.observations.size(); i-- > 0;) first[r.observations[i].point] = i;
  return first;
}

void CopyAttributes(const SfmReconstruction& r, std::uint32_t point, LabelledCloud* cloud) {
  cloud->positions_world.push_back(r.points_world[point]);
  if (!r.point_colors_rgb.empty()) cloud->colors_rgb.push_back(r.point_colors_rgb[point]);
  if (!r.point_labels.empty()) cloud->labels.push_back(r.point_labels[point]);
}

}  // namespace

SfmBatchInput MakeBatchInput(const SfmReconstruction& r) {
  r.AssertConsistent();
  SfmBatchInput in;
  for (std::uint32_t v = 0; v < r.views.size(); ++v) {
    in.cloud.camera_centers_world.push_back(r.views[v].center_world());
    in.cloud.camera_frame_ids.push_back(v);
  }
  const std::vector<std::size_t> first = FirstObservation(r);
  std::vector<std::uint32_t> cloud_index(r.num_points(), 0);
  for (std::uint32_t p = 0; p < r.num_points(); ++p) {
    if (first[p] == SIZE_MAX) {
      ++in.unobserved_points;
      continue;
    }
    cloud_index[p] = static_cast<std::uint32_t>(in.cloud.size());
    in.point_index.push_back(p);
    CopyAttributes(r, p, &in.cloud);
    in.cloud.camera_index.push_back(r.observations[first[p]].view);
  }
  for (std::size_t i = 0; i < r.observations.size(); ++i) {
    const SfmObservation& o = r.observations[i];
    const bool repeated =
        i > 0 && r.observations[i - 1].point == o.point && r.observations[i - 1].view == o.view;
    if (first[o.point] != i && !repeated) in.extra.push_back({cloud_index[o.point], o.view});
  }
  return in;
}

std::vector<SfmKeyframe> MakeKeyframes(const SfmReconstruction& r) {
  r.AssertConsistent();
  std::vector<SfmKeyframe> keyframes(r.views.size());
  for (std::uint32_t v = 0; v < keyframes.size(); ++v) keyframes[v].view = v;
  // Observations are sorted by (point, view): a point's first entry is its first view; repeated (point,
  // view) pairs are adjacent.
  for (std::size_t i = 0; i < r.observations.size(); ++i) {
    const SfmObservation& o = r.observations[i];
    const bool first_of_point = i == 0 || r.observations[i - 1].point != o.point;
    if (first_of_point) {
      keyframes[o.view].new_points.push_back(o.point);
    } else if (r.observations[i - 1].view != o.view) {
      keyframes[o.view].seen_points.push_back(o.point);
    }
  }
  return keyframes;
}

LabelledCloud KeyframeCloud(const SfmReconstruction& r, const SfmKeyframe& k) {
  LabelledCloud cloud;
  cloud.camera_centers_world.push_back(r.views[k.view].center_world());
  cloud.camera_frame_ids.push_back(k.view);
  cloud.positions_world.reserve(k.new_points.size());
  for (std::uint32_t p : k.new_points) CopyAttributes(r, p, &cloud);
  cloud.camera_index.assign(k.new_points.size(), 0);
  return cloud;
}

bool SimplifiesSfm(const SfmReconstruction& r, const SimplifyOptions& simplify) {
  return simplify.method != SimplifyMethod::kOriginal && !r.point_labels.empty();
}

SfmBatchResult MapSfmBatch(const SfmReconstruction& r, const MapOptions& map, const SimplifyOptions& simplify,
                           const ClassMap& class_map) {
  map.Check();
  simplify.Check();
  SfmBatchInput in = MakeBatchInput(r);
  SfmBatchResult out;
  out.points_in = in.cloud.size();
  out.unobserved_points = in.unobserved_points;
  if (SimplifiesSfm(r, simplify)) {
    const auto t0 = std::chrono::steady_clock::now();
    const SimplifyResult kept = Simplify(in.cloud, class_map, simplify);
    std::vector<std::uint32_t> new_index(in.cloud.size(), kDroppedPoint);
    for (std::uint32_t i = 0; i < kept.kept_indices.size(); ++i) new_index[kept.kept_indices[i]] = i;
    in.cloud = ApplySimplification(in.cloud, kept);
    std::vector<Observation> extra;
    for (const Observation& o : in.extra) {
      if (new_index[o.point] != kDroppedPoint) extra.push_back({new_index[o.point], o.camera});
    }
    in.extra = std::move(extra);
    out.simplify_s = SecondsSince(t0);
  }
  out.points_kept = in.cloud.size();
  out.rays = in.cloud.size() + in.extra.size();
  const auto t0 = std::chrono::steady_clock::now();
  BatchMapResult result = BuildBatchMap(map, in.cloud, in.extra);
  out.map_s = SecondsSince(t0);
  out.mesh = std::move(result.mesh);
  out.statistics = result.statistics;
  return out;
}

namespace {
// SfM tracks come without depth maps: their visibility is always the exact rays (a point per track, a ray
// per observation).
MapOptions WithRayVisibility(MapOptions map) {
  map.visibility = Visibility::kRays;
  return map;
}
}  // namespace

SfmIncrementalMapper::SfmIncrementalMapper(const SfmReconstruction& reconstruction, const MapOptions& map,
                                           const SimplifyOptions& simplify, ClassMap class_map)
    : reconstruction_(&reconstruction),
      keyframes_(MakeKeyframes(reconstruction)),
      map_(WithRayVisibility(map)),
      simplify_(SimplifiesSfm(reconstruction, simplify)),
      map_id_(reconstruction.num_points(), kUnseen) {
  simplify.Check();
  if (simplify_) simplifier_ = std::make_unique<WindowedSimplifier>(simplify, std::move(class_map));
}

SfmKeyframeResult SfmIncrementalMapper::Step() {
  SEMAP_ASSERT(!done(), "no keyframe left");
  const SfmReconstruction& r = *reconstruction_;
  const SfmKeyframe& k = keyframes_[next_++];
  SfmKeyframeResult out;
  out.view = k.view;
  out.new_points = k.new_points.size();

  // New points, simplified.
  LabelledCloud cloud = KeyframeCloud(r, k);
  std::vector<std::uint32_t> points = k.new_points;  // reconstruction point of each cloud point
  if (simplify_) {
    const auto t0 = std::chrono::steady_clock::now();
    WindowedSimplifier::FrameResult kept = simplifier_->Process(cloud);
    for (std::uint32_t p : k.new_points) map_id_[p] = kSimplifiedAway;
    std::vector<std::uint32_t> kept_points;
    kept_points.reserve(kept.result.kept_indices.size());
    for (std::uint32_t i : kept.result.kept_indices) kept_points.push_back(points[i]);
    points = std::move(kept_points);
    cloud = std::move(kept.kept);
    for (const ClassSimplifyStats& c : kept.result.per_class) {
      out.class_counts.push_back(
          {c.label, static_cast<std::int64_t>(c.in), static_cast<std::int64_t>(c.kept)});
    }
    out.simplify_s = SecondsSince(t0);
  }
  out.kept_points = points.size();

  // Rays to points already in the map (one per point: repeated observations by this view are one ray).
  std::vector<Observation> extra;
  extra.reserve(k.seen_points.size());
  std::unordered_set<std::uint32_t> seen_ids;
  for (std::uint32_t p : k.seen_points) {
    const std::uint32_t id = map_id_[p];
    if (id >= kFirstMarker || id == kDroppedPoint) {
      ++out.observations_skipped;
    } else if (seen_ids.insert(id).second) {
      extra.push_back({id, 0});
    }
  }
  out.observations = extra.size();

  const auto t0 = std::chrono::steady_clock::now();
  const MapUpdateResult update = map_.Update(cloud, extra);
  out.map_s = SecondsSince(t0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    map_id_[points[i]] = update.point_ids[i];
    if (update.point_ids[i] != kDroppedPoint) mapped_points_.push_back(points[i]);
  }
  if (update.points_finalised > 0) {
    const auto t_live = std::chrono::steady_clock::now();
    RefreshLivePoints();
    out.live_s = SecondsSince(t_live);
  }
  out.inserted = update.inserted;
  out.merged = update.merged;
  out.dropped = update.dropped;
  out.finalised = update.points_finalised;

  const auto t1 = std::chrono::steady_clock::now();
  const IdentifiedMesh finalised = map_.TakeFinalisedMesh();
  out.delta = differ_.Update(k.view, map_.ExtractIdentifiedMesh(), finalised);
  published_triangles_ += static_cast<std::int64_t>(out.delta.added_triangle_ids.size()) -
                          static_cast<std::int64_t>(out.delta.removed_triangle_ids.size());
  out.mesh_s = SecondsSince(t1);
  out.mesh_triangles = published_triangles_;
  out.statistics = map_.Statistics();
  return out;
}

MeshDelta SfmIncrementalMapper::Finish() {
  const std::int64_t last_view = keyframes_.empty() ? -1 : static_cast<std::int64_t>(keyframes_.back().view);
  return differ_.Update(last_view, map_.ExtractIdentifiedMesh(), map_.TakeFinalisedMesh());
}

// The map does not say which points it finalised: its snapshot lists the live ones. Called only after an
// update that finalised points (every MapOptions::finalise_every_frames frames at most).
void SfmIncrementalMapper::RefreshLivePoints() {
  const MapSnapshot snapshot = map_.ExportSnapshot();
  const std::unordered_set<std::uint32_t> live(snapshot.point_ids.begin(), snapshot.point_ids.end());
  std::size_t kept = 0;
  for (std::uint32_t p : mapped_points_) {
    if (live.count(map_id_[p])) {
      mapped_points_[kept++] = p;
    } else {
      map_id_[p] = kFinalised;
    }
  }
  mapped_points_.resize(kept);
}

}  // namespace semap::app
