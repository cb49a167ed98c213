#include "tools/engine_run.h"

#include <stdexcept>

#include "engine/pipeline/semap_stages.h"
#include "io/frame_source.h"
#include "io/output/output_sinks.h"
#include "tools/progress_sink.h"

namespace semap::tools {

EngineRun RunAndEvaluate(const io::Config& config, const std::string& dataset, double progress_s,
                         std::unique_ptr<SimplifyStage> simplify, const std::vector<PipelineSink*>& extra_sinks) {
  auto source = io::OpenFrameSource(dataset, config.input);
  const std::int64_t total = source->size();
  const ClassMap class_map = source->class_map();
  io::MeshFileSink mesh_sink(config.output);
  std::unique_ptr<io::StatsFileSink> stats_sink;
  if (config.output.frame_stats) stats_sink = std::make_unique<io::StatsFileSink>(config.output);
  std::unique_ptr<ProgressSink> progress;
  if (progress_s > 0.0) progress = std::make_unique<ProgressSink>(total, progress_s);

  Pipeline pipeline(
      config.pipeline, std::move(source),
      [&] { return std::make_unique<StereoLabelStage>(config.depth, config.semantics, class_map); },
      simplify ? std::move(simplify) : std::make_unique<WindowedSimplifyStage>(config.simplify, class_map),
      std::make_unique<IncrementalMapStage>(config.map));
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
