// semap_stage_cpu: the CPU time of each stage of `semap run` per frame, one stage after the other on one
// thread (TBB limited to one thread, OpenCV to one), so that each figure is that stage's own work and does
// not depend on how busy the machine is (CPU time, not wall time: on a shared machine wall time drifts, CPU
// time far less). The same stages and options as `semap run` (app/run/engine_pipeline.cc): the frame source,
// ENet on keyframes (semantics.source enet, semantics.enet_every_frames; the frames between labelled from
// their keyframe), the reader's row alignment (depth.align_rows), the depth stage (SGBM + labels), the
// windowed simplifier and the incremental map.
//
// Usage: semap_stage_cpu SEQUENCE [--frames N] [--config FILE] [--set section.key=value ...] [--csv FILE]
//
// Prints, per stage, the mean / median / 95th percentile / max CPU ms per frame (segment: per keyframe, and
// its mean per frame), the sum, and what they bound on two cores: the pipeline runs read, segment, simplify
// and map on one thread each and depth on pipeline.depth_workers threads, so the rate is at most
// 1000 / (CPU ms of the slowest single-thread stage) and 2000 / (CPU ms of all stages) frames per second.
// --csv writes one line per frame with every stage's CPU ms.
#include <tbb/global_control.h>
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "app/run/engine_pipeline.h"
#include "engine/pipeline/semap_stages.h"
#include "engine/semantics/keyframe_labels.h"

namespace {

double CpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

struct Series {
  std::vector<double> ms;
  double Mean() const {
    double s = 0.0;
    for (double v : ms) s += v;
    return ms.empty() ? 0.0 : s / static_cast<double>(ms.size());
  }
  double Quantile(double q) const {  // nearest rank
    if (ms.empty()) return 0.0;
    std::vector<double> v = ms;
    std::sort(v.begin(), v.end());
    const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(k, v.size() - 1)];
  }
  double Max() const { return ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()); }
};

// The stages of `semap run`, one after the other on this thread, with the CPU ms each took per frame.
class StageRunner {
 public:
  StageRunner(const semap::app::Config& config, const std::string& sequence)
      : config_(config),
        source_(semap::app::OpenStreamingSource(config, sequence)),
        class_map_(source_->class_map()),
        // ENet on keyframes as `semap run` does (every_frames 1: every frame in the depth stage, as there).
        keyframes_(config.semantics.source == semap::LabelSource::kEnet &&
                   config.semantics.enet_every_frames > 1),
        depth_(config.depth, config.semantics, class_map_, keyframes_),
        simplify_(config.simplify, class_map_),
        map_(config.map, config.pipeline.mesh_every_frames),
        schedule_(keyframes_ ? config.semantics.enet_every_frames : 1) {
    // The reader of `semap run` measures the pair's row offsets (depth.align_rows) on the first frames, then
    // every 100, and hands them to the depth stage with each frame: its cost is the read stage's, as there.
    reader_ = std::move(source_);
    if (config.depth.align_rows) reader_ = std::make_unique<semap::RowAlignmentReader>(std::move(reader_));
    if (keyframes_) segment_ = std::make_unique<semap::SegmenterStage>(config.semantics);
  }

  // Runs every stage on the next frame and records their CPU ms (and a --csv line); false after the last.
  bool Next(std::ofstream& csv) {
    double t = CpuMs();
    std::optional<semap::Frame> frame = reader_->Next();
    if (!frame) return false;
    const double read_ms = CpuMs() - t;
    const double segment_ms = SegmentIfKeyframe(*frame);
    t = CpuMs();
    semap::LabelledCloud cloud = depth_.Process(*frame, keyframes_ ? &keyframe_ : nullptr);
    const double depth_ms = CpuMs() - t;
    const auto points_in = cloud.size();
    t = CpuMs();
    std::vector<semap::ClassPointCount> counts;
    cloud = simplify_.Process(std::move(cloud), &counts);
    const double simplify_ms = CpuMs() - t;
    t = CpuMs();
    if (!frame->world_from_cam)
      throw std::runtime_error("frame " + std::to_string(frame->id) + " has no pose");
    map_.Process(cloud, *frame->world_from_cam);
    const double map_ms = CpuMs() - t;
    stages_["read"].ms.push_back(read_ms);
    stages_["depth"].ms.push_back(depth_ms);
    stages_["simplify"].ms.push_back(simplify_ms);
    stages_["map"].ms.push_back(map_ms);
    if (csv) {
      csv << frame->id << ',' << read_ms << ',' << segment_ms << ',' << depth_ms << ',' << simplify_ms << ','
          << map_ms << ',' << points_in << ',' << cloud.size() << '\n';
    }
    ++frames_;
    return true;
  }

  // The map's end of drive; its CPU ms.
  double Finish() {
    const double t = CpuMs();
    map_.Finish();
    return CpuMs() - t;
  }

  // The summary: per stage, mean / median / p95 / max CPU ms per frame, the sum, and the bounds on two cores.
  void PrintTable(const std::string& sequence, double finish_ms) {
    const std::vector<std::string> order = {"read", "segment", "depth", "simplify", "map"};
    std::printf(
        "%s: %lld frames; simplify.method %s, depth.half_resolution %s, semantics.source %s, "
        "enet_every_frames %d, ENet input %dx%d\n",
        sequence.c_str(), static_cast<long long>(frames_), semap::SimplifyMethodName(config_.simplify.method),
        config_.depth.half_resolution ? "true" : "false", semap::LabelSourceName(config_.semantics.source),
        config_.semantics.enet_every_frames, config_.semantics.enet_input_width_px,
        config_.semantics.enet_input_height_px);
    std::printf("| stage | CPU ms / frame (mean) | median | p95 | max |\n|---|---:|---:|---:|---:|\n");
    double sum = 0.0, slowest_single = 0.0;
    std::string slowest_name;
    for (const auto& name : order) {
      if (!stages_.count(name)) continue;
      const double per_frame = PrintStage(name);
      sum += per_frame;
      // depth runs on pipeline.depth_workers threads: its single-thread bound is per worker.
      const double single = name == "depth" ? per_frame / config_.pipeline.depth_workers : per_frame;
      if (single > slowest_single) {
        slowest_single = single;
        slowest_name = name;
      }
    }
    std::printf("| all stages | %.1f | | | |\n\nmap finish (once): %.0f ms CPU\n", sum, finish_ms);
    const semap::MapStatistics counts = map_.Statistics();
    std::printf(
        "map: %zu live vertices at the end; vertices moved to their fused estimate %llu, outliers removed "
        "%llu\n",
        counts.num_points, static_cast<unsigned long long>(counts.vertices_moved),
        static_cast<unsigned long long>(counts.vertices_outliers));
    std::printf(
        "bounds on 2 cores: %.2f f/s from all stages' CPU (2000 / %.0f ms), %.2f f/s from the slowest "
        "single-thread stage (%s, 1000 / %.0f ms)\n",
        2000.0 / sum, sum, 1000.0 / slowest_single, slowest_name.c_str(), slowest_single);
  }

  std::int64_t frames() const { return frames_; }

 private:
  // ENet on the frame when it is due as a keyframe; its CPU ms (0 otherwise).
  double SegmentIfKeyframe(const semap::Frame& frame) {
    if (!keyframes_) return 0.0;
    const bool has_pose = frame.world_from_cam.has_value();
    if (!schedule_.IsDue(frame.id, has_pose)) return 0.0;
    schedule_.Record(frame.id, has_pose);
    const double t = CpuMs();
    keyframe_.frame_id = frame.id;
    keyframe_.world_from_cam = frame.world_from_cam;
    keyframe_.labels = segment_->Process(frame);
    const double segment_ms = CpuMs() - t;
    stages_["segment"].ms.push_back(segment_ms);
    segment_total_ms_ += segment_ms;
    ++keyframe_count_;
    return segment_ms;
  }

  // Prints a stage's row (segment: per keyframe and per frame); returns its mean CPU ms per frame.
  double PrintStage(const std::string& name) {
    const Series& s = stages_[name];
    if (name != "segment") {
      std::printf("| %s | %.1f | %.1f | %.1f | %.1f |\n", name.c_str(), s.Mean(), s.Quantile(0.5),
                  s.Quantile(0.95), s.Max());
      return s.Mean();
    }
    const double per_frame = segment_total_ms_ / static_cast<double>(frames_);
    std::printf("| segment (per keyframe, %lld keyframes) | %.1f | %.1f | %.1f | %.1f |\n",
                static_cast<long long>(keyframe_count_), s.Mean(), s.Quantile(0.5), s.Quantile(0.95),
                s.Max());
    std::printf("| segment (per frame) | %.1f | | | |\n", per_frame);
    return per_frame;
  }

  const semap::app::Config& config_;
  std::unique_ptr<semap::io::FrameSource> source_;
  const semap::ClassMap class_map_;
  std::unique_ptr<semap::FrameReader> reader_;
  const bool keyframes_;
  std::unique_ptr<semap::SegmenterStage> segment_;
  semap::StereoLabelStage depth_;
  semap::WindowedSimplifyStage simplify_;
  semap::IncrementalMapStage map_;
  semap::KeyframeSchedule schedule_;
  semap::KeyframeLabels keyframe_;
  std::map<std::string, Series> stages_;  // per frame (segment: per keyframe)
  std::int64_t frames_ = 0, keyframe_count_ = 0;
  double segment_total_ms_ = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"CPU ms per frame of each stage of semap run, one stage after the other on one thread"};
  std::string sequence, config_path, csv_path;
  std::vector<std::string> overrides;
  int max_frames = 0;
  app.add_option("SEQUENCE", sequence, "dataset folder (what semap run reads)")->required();
  app.add_option("--frames", max_frames, "frames to process (0 = all)");
  app.add_option("--config", config_path, "YAML config");
  app.add_option("--set", overrides, "section.key=value overrides (as semap run --set)");
  app.add_option("--csv", csv_path, "per-frame CPU ms of each stage");
  CLI11_PARSE(app, argc, argv);
  try {
    if (max_frames > 0) overrides.push_back("input.max_frames=" + std::to_string(max_frames));
    const semap::app::Config config = semap::app::LoadConfig(config_path, overrides);
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    cv::setNumThreads(1);
    StageRunner runner(config, sequence);
    std::ofstream csv;
    if (!csv_path.empty()) {
      csv.open(csv_path);
      if (!csv) throw std::runtime_error(csv_path + ": cannot write");
      csv << "frame_id,read_ms,segment_ms,depth_ms,simplify_ms,map_ms,points_in,points_kept\n";
    }
    while (runner.Next(csv)) {
    }
    if (runner.frames() == 0) throw std::runtime_error(sequence + ": no frame");
    const double finish_ms = runner.Finish();
    runner.PrintTable(sequence, finish_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_stage_cpu: %s\n", e.what());
    return 1;
  }
  return 0;
}
