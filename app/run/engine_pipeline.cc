#include "app/run/engine_pipeline.h"

#include <spdlog/spdlog.h>

#include <functional>
#include <string>

#include "engine/pipeline/semap_stages.h"
#include "io/frame_source.h"

namespace semap::app {

namespace {

// The frames of a source, passed on as they are; a label image of another size than its frame is reported
// (the label stage resizes it with nearest neighbour: semantics.size_mismatch = resize).
class LabelSizeWarnings : public FrameReader {
 public:
  explicit LabelSizeWarnings(std::unique_ptr<io::FrameSource> source) : source_(std::move(source)) {}
  std::optional<Frame> Next() override {
    std::optional<Frame> f = source_->Next();
    if (f && !f->labels.empty() && f->labels.size() != f->left.size()) {
      spdlog::warn("frame {}: label image {}x{} resized (nearest neighbour) to the image size {}x{}", f->id,
                   f->labels.cols, f->labels.rows, f->left.cols, f->left.rows);
    }
    return f;
  }

 private:
  std::unique_ptr<io::FrameSource> source_;
};

// Each depth worker's stage: SGBM (or the plane sweep) and the labels, from its keyframe's labels when
// `labels_from_keyframes` (no segmenter of its own), else from the frame's (ENet run here with
// semantics.source enet).
std::function<std::unique_ptr<StereoLabelStage>()> StereoLabelStages(const Config& config,
                                                                     const ClassMap& class_map,
                                                                     bool labels_from_keyframes) {
  return [depth = config.depth, semantics = config.semantics, sweep = config.plane_sweep, class_map,
          labels_from_keyframes] {
    return std::make_unique<StereoLabelStage>(depth, semantics, class_map, labels_from_keyframes, sweep);
  };
}

// A pipeline that maps what its depth stages give: `simplify` (or the configured windowed simplification
// when null), then the incremental map.
std::unique_ptr<Pipeline> MappingPipeline(const Config& config, std::unique_ptr<FrameReader> reader,
                                          DepthStageFactory depth, const ClassMap& class_map,
                                          std::unique_ptr<SimplifyStage> simplify) {
  if (!simplify) simplify = std::make_unique<WindowedSimplifyStage>(config.simplify, class_map);
  return std::make_unique<Pipeline>(
      config.pipeline, std::move(reader), std::move(depth), std::move(simplify),
      std::make_unique<IncrementalMapStage>(config.map, config.pipeline.MeshEveryFrames()));
}

}  // namespace

std::unique_ptr<io::FrameSource> OpenStreamingSource(const Config& config, const std::string& dataset) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  input.load_labels =
      config.semantics.source == LabelSource::kAuto || config.semantics.source == LabelSource::kDisk;
  return io::OpenFrameSource(dataset, input);
}

std::unique_ptr<Pipeline> MakeEnginePipeline(const Config& config, std::unique_ptr<io::FrameSource> source,
                                             std::unique_ptr<SimplifyStage> simplify,
                                             const RunOdometry* odometry, const DepthNodeWiring* depth_node) {
  const ClassMap class_map = source->class_map();
  std::unique_ptr<FrameReader> reader;
  if (config.semantics.size_mismatch == LabelSizePolicy::kResizeNearest) {
    reader = std::make_unique<LabelSizeWarnings>(std::move(source));
  } else {
    reader = std::move(source);
  }
  if (config.depth.align_rows) reader = std::make_unique<RowAlignmentReader>(std::move(reader));
  if (odometry != nullptr && odometry->log) {
    reader = std::make_unique<OdometryReader>(std::move(reader), config.odometry,
                                              odometry->plan.replace_poses, odometry->log);
  }
  if (config.plane_sweep.stereo_past_frames > 0) {
    reader =
        std::make_unique<StereoNeighbourReader>(std::move(reader), config.plane_sweep.stereo_past_frames);
  }
  // Last: the readers before see every frame of the sequence, as they do in a single process.
  if (depth_node) reader = std::make_unique<FrameShareReader>(std::move(reader), depth_node->share);
  // ENet on keyframes (semantics.enet_every_frames > 1) runs on its own thread and the depth workers load
  // none; on every frame (1) each depth worker runs its own, so that the workers segment frames in parallel
  // (one segment thread would be a single lane of ENet: slower on two cores, and nothing to take off the
  // path).
  const bool enet = config.semantics.source == LabelSource::kEnet && config.semantics.enet_every_frames > 1;
  const auto make_stage = StereoLabelStages(config, class_map, enet);
  std::unique_ptr<Pipeline> pipeline;
  if (depth_node) {
    pipeline = std::make_unique<Pipeline>(
        config.pipeline, std::move(reader),
        [make_stage, sink = depth_node->sink]() -> std::unique_ptr<DepthStage> {
          return std::make_unique<FrameDepthStage>(make_stage(), sink);
        },
        std::make_unique<PassThroughSimplifyStage>(), std::make_unique<NoMapStage>());
  } else {
    pipeline = MappingPipeline(config, std::move(reader), make_stage, class_map, std::move(simplify));
  }
  if (enet) {
    pipeline->SetSegmentStage(std::make_unique<SegmenterStage>(config.semantics),
                              config.semantics.enet_every_frames);
  }
  return pipeline;
}

std::unique_ptr<Pipeline> MakeMapNodePipeline(const Config& config, std::unique_ptr<FrameReader> frames,
                                              const ClassMap& class_map,
                                              std::unique_ptr<SimplifyStage> simplify) {
  // The frames carry their labels: no segmenter (labels_from_keyframes).
  return MappingPipeline(config, std::move(frames),
                         StereoLabelStages(config, class_map, /*labels_from_keyframes=*/true), class_map,
                         std::move(simplify));
}

}  // namespace semap::app
