#include "tools/engine_run.h"

#include <stdexcept>

#include "engine/pipeline/semap_stages.h"
#include "io/frame_source.h"
#include "io/output/output_sinks.h"
#include "tools/progress_sink.h"

namespace semap::tools {

std::unique_ptr<io::FrameSource> OpenStreamingSource(const io::Config& config, const std::string& dataset) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  return io::OpenFrameSource(dataset, input);
}

std::unique_ptr<Pipeline> MakeEnginePipeline(const io::Config& config, std::unique_ptr<io::FrameSource> source,
                                             std::unique_ptr<SimplifyStage> simplify) {
  const ClassMap class_map = source->class_map();
  if (!simplify) simplify = std::make_unique<WindowedSimplifyStage>(config.simplify, class_map);
  return std::make_unique<Pipeline>(
      config.pipeline, std::move(source),
      [depth = config.depth, semantics = config.semantics, class_map] {
        return std::make_unique<StereoLabelStage>(depth, semantics, class_map);
      },
      std::move(simplify), std::make_unique<IncrementalMapStage>(config.map));
}

EngineRun RunAndEvaluate(const io::Config& config, const std::string& dataset, double progress_s,
                         std::unique_ptr<SimplifyStage> simplify, const std::vector<PipelineSink*>& extra_sinks) {
  auto source = OpenStreamingSource(config, dataset);
  const std::int64_t total = source->size();
  io::MeshFileSink mesh_sink(config.output);
  std::unique_ptr<io::StatsFileSink> stats_sink;
  if (config.output.frame_stats) stats_sink = std::make_unique<io::StatsFileSink>(config.output);
  std::unique_ptr<ProgressSink> progress;
  if (progress_s > 0.0) progress = std::make_unique<ProgressSink>(total, progress_s);

  const std::unique_ptr<Pipeline> engine = MakeEnginePipeline(config, std::move(source), std::move(simplify));
  Pipeline& pipeline = *engine;
  pipeline.AddSink(&mesh_sink);
  if (stats_sink) pipeline.AddSink(stats_sink.get());
  if (progress) pipeline.AddSink(progress.get());
  for (PipelineSink* sink : extra_sinks) pipeline.AddSink(sink);
  EngineRun run;
  run.summary = pipeline.Run();
  if (!run.summary.fatal_error.empty()) throw std::runtime_error("run stopped: " + run.summary.fatal_error);
  if (run.summary.sink_errors > 0) throw std::runtime_error("output error: " + run.summary.first_sink_error);
  run.mesh = mesh_sink.mesh();
  run.evaluation = io::EvaluateMesh(run.mesh, dataset, config.input, config.eval);
  return run;
}

}  // namespace semap::tools
