#include "app/sfm/map_sfm_run.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include "app/run/progress_sink.h"
#include "app/run/run_outputs.h"
#include "app/sfm/sfm_mapping.h"
#include "engine/pipeline/pipeline.h"
#include "engine/pipeline/timing_stats.h"
#include "io/labels/class_map_yaml.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

// Peak resident set size of this process in MiB (VmHWM), 0 if unknown.
double PeakRssMb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    long kb = 0;
    if (std::sscanf(line.c_str(), "VmHWM: %ld kB", &kb) == 1) return static_cast<double>(kb) / 1024.0;
  }
  return 0.0;
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The run's outputs and its progress line, fed by the mapping loop itself (no pipeline).
struct Sinks {
  Sinks(const Config& config, std::int64_t keyframes, double progress_s)
      : outputs(config), progress(keyframes, progress_s) {}
  template <typename F>
  void ForEach(F f) {
    for (PipelineSink* sink : outputs.sinks()) f(*sink);
    f(progress);
  }
  RunOutputs outputs;
  ProgressSink progress;
};

// Per-keyframe stage timings as the run's FrameStats report them.
class StageTimings {
 public:
  void Add(std::initializer_list<std::pair<const char*, double>> seconds) {
    if (stats_.empty()) {
      for (const auto& s : seconds) names_.push_back(s.first);
      stats_.resize(names_.size());
    }
    std::size_t i = 0;
    for (const auto& s : seconds) stats_[i++].Add(1e3 * s.second);
  }
  std::vector<StageTiming> Report() const {
    std::vector<StageTiming> out;
    for (std::size_t i = 0; i < stats_.size(); ++i) {
      const TimingStats& t = stats_[i];
      out.push_back({names_[i], t.last(), t.mean(), t.Percentile(0.5), t.Percentile(0.95), t.max(), 0});
    }
    return out;
  }

 private:
  std::vector<std::string> names_;
  std::vector<TimingStats> stats_;
};

void FillMap(const MapStatistics& m, FrameStats* s) {
  s->map_vertices = static_cast<std::int64_t>(m.num_points + m.num_steiner_vertices);
  s->map_cells = static_cast<std::int64_t>(m.num_cells);
  s->map_rays = static_cast<std::int64_t>(m.num_rays);
}

void RunBatch(const io::SfmReconstruction& r, const Config& config, const ClassMap& class_map, Sinks* sinks,
              FrameStats* final_stats) {
  const auto t0 = std::chrono::steady_clock::now();
  SfmBatchResult result = MapSfmBatch(r, config.map, config.simplify, class_map);
  if (result.unobserved_points > 0)
    spdlog::warn("{} points no view observes were left out", result.unobserved_points);
  spdlog::info("batch map: {} points ({} kept), {} rays, simplification {:.3f} s, map {:.3f} s",
               result.points_in, result.points_kept, result.rays, result.simplify_s, result.map_s);
  IdentifiedMesh mesh;
  mesh.mesh = std::move(result.mesh);
  for (std::size_t i = 0; i < mesh.mesh.num_vertices(); ++i) mesh.vertex_ids.push_back(i);
  MeshDiffer differ;
  const MeshDelta delta = differ.Update(0, mesh);

  StageTimings timings;
  timings.Add({{"simplify", result.simplify_s}, {"map", result.map_s}});
  FrameStats& s = *final_stats;
  s.frame_id = 0;
  s.frames_processed = 1;
  s.elapsed_s = SecondsSince(t0);
  s.fps = s.elapsed_s > 0.0 ? 1.0 / s.elapsed_s : 0.0;
  s.stages = timings.Report();
  s.points_in = static_cast<std::int64_t>(result.points_in);
  s.points_kept = static_cast<std::int64_t>(result.points_kept);
  FillMap(result.statistics, &s);
  s.mesh_triangles = static_cast<std::int64_t>(mesh.mesh.num_triangles());
  s.rss_mb = CurrentRssMb();
  sinks->ForEach([&](PipelineSink& sink) { sink.OnFrame(s, delta, std::nullopt); });
  sinks->ForEach([&](PipelineSink& sink) { sink.OnFinish(s, MeshDelta{}); });
}

void RunIncremental(const io::SfmReconstruction& r, const Config& config, const ClassMap& class_map,
                    Sinks* sinks, FrameStats* final_stats) {
  SfmIncrementalMapper mapper(r, config.map, config.simplify, class_map);
  StageTimings timings;
  TimingStats keyframe_ms;
  FrameStats s;
  std::size_t observations = 0, skipped = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!mapper.done()) {
    SfmKeyframeResult k = mapper.Step();
    timings.Add({{"simplify", k.simplify_s}, {"map", k.map_s}, {"live", k.live_s}, {"mesh", k.mesh_s}});
    keyframe_ms.Add(1e3 * (k.simplify_s + k.map_s + k.live_s + k.mesh_s));
    observations += k.observations;
    skipped += k.observations_skipped;
    ++s.frames_processed;
    s.frame_id = k.view;
    s.timestamp_s = static_cast<double>(k.view);
    s.elapsed_s = SecondsSince(t0);
    s.fps = s.elapsed_s > 0.0 ? static_cast<double>(s.frames_processed) / s.elapsed_s : 0.0;
    s.stages = timings.Report();
    s.points_in = static_cast<std::int64_t>(k.new_points);
    s.points_kept = static_cast<std::int64_t>(k.kept_points);
    s.class_counts = std::move(k.class_counts);
    FillMap(k.statistics, &s);
    s.mesh_triangles = k.mesh_triangles;
    s.rss_mb = CurrentRssMb();
    const Pose3d pose = r.views[k.view].world_from_cam;
    sinks->ForEach([&](PipelineSink& sink) { sink.OnFrame(s, k.delta, pose); });
  }
  const MeshDelta last = mapper.Finish();
  s.elapsed_s = SecondsSince(t0);
  sinks->ForEach([&](PipelineSink& sink) { sink.OnFinish(s, last); });
  spdlog::info("{} keyframes in {:.2f} s: per keyframe mean {:.1f} ms, p50 {:.1f}, p95 {:.1f}, max {:.1f}",
               s.frames_processed, s.elapsed_s, keyframe_ms.mean(), keyframe_ms.Percentile(0.5),
               keyframe_ms.Percentile(0.95), keyframe_ms.max());
  spdlog::info(
      "{} extra rays to earlier points; {} observations skipped (simplified away, dropped or finalised)",
      observations, skipped);
  *final_stats = s;
}

}  // namespace

void MapSfm(const Config& config, const MapSfmRequest& request) {
  const io::SfmFormat format = request.format;
  const ClassMap class_map = io::LoadClassMap(config.input.class_map);  // empty = Cityscapes

  const auto t_read = std::chrono::steady_clock::now();
  io::SfmReconstruction r = io::ReadSfm(request.input, format);
  const double limit_m = MaxSfmCoordinateM(config.map);
  if (const FarPoints far = DropFarPoints(request.input, limit_m, &r); far.count > 0) {
    spdlog::warn("{}: {} point(s) with a coordinate beyond {} m were left out (first: point id {})",
                 request.input.string(), far.count, limit_m, far.first_id);
  }
  spdlog::info("{} ({}): {} views, {} points, {} observations, {}, read in {:.2f} s", request.input.string(),
               io::SfmFormatName(format), r.views.size(), r.num_points(), r.observations.size(),
               r.point_labels.empty() ? "no labels" : "labelled", SecondsSince(t_read));
  if (r.views.empty()) throw io::FileError(request.input, "the reconstruction has no posed view");
  if (SimplifiesSfm(r, config.simplify)) {
    spdlog::info("simplification: method {}", SimplifyMethodName(config.simplify.method));
  } else {
    spdlog::info("simplification: none ({})",
                 r.point_labels.empty() ? "the points have no labels" : "method O");
  }

  // Sinks first: an unusable output folder or LCM URL is reported before any work is done.
  Sinks sinks(config, request.incremental ? static_cast<std::int64_t>(r.views.size()) : 1,
              request.progress_s);
  FrameStats final_stats;
  if (request.incremental) {
    RunIncremental(r, config, class_map, &sinks, &final_stats);
  } else {
    RunBatch(r, config, class_map, &sinks, &final_stats);
  }

  const Mesh mesh = sinks.outputs.mesh();
  spdlog::info("mesh: {} vertices, {} triangles, {:.2f} MB as OFF; peak RSS {:.0f} MB", mesh.num_vertices(),
               mesh.num_triangles(), static_cast<double>(io::OffSizeBytes(mesh)) / 1e6, PeakRssMb());
  sinks.outputs.LogWritten();
}

}  // namespace semap::app
