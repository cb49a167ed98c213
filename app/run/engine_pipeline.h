// The streaming engine as a run's configuration assembles it: the frame source and the pipeline of stages
// (app/run/stream_run.h adds the sinks and runs it).
#pragma once

#include <memory>
#include <string>

#include "app/config/config.h"
#include "app/run/odometry_reader.h"
#include "app/split/depth_node.h"
#include "engine/pipeline/pipeline.h"
#include "engine/pipeline/stages.h"
#include "io/frame_source.h"

namespace semap::app {

// The frame source of a streaming run: the dataset with config.input, except that Velodyne scans are not
// loaded (they serve evaluation only, so a missing one must not cost a frame).
std::unique_ptr<io::FrameSource> OpenStreamingSource(const Config& config, const std::string& dataset);

// A split run's depth node: where each frame's depth goes (not owned), and which frames are this node's.
struct DepthNodeWiring {
  FrameDepthSink* sink = nullptr;
  FrameShare share;
};

// The engine's stages on `source` as `config` says: SGBM + labels, `simplify` (or the configured windowed
// simplification when null), the incremental map. With `odometry` (its log not null), visual odometry runs in
// the reader as its plan says (OdometryReader). With `depth_node`, only the frames of its share go through,
// the depth stage hands each frame's depth and labels to its sink (FrameDepthStage), and there is no
// simplification and no map. Sinks are the caller's to add.
std::unique_ptr<Pipeline> MakeEnginePipeline(const Config& config, std::unique_ptr<io::FrameSource> source,
                                             std::unique_ptr<SimplifyStage> simplify = nullptr,
                                             const RunOdometry* odometry = nullptr,
                                             const DepthNodeWiring* depth_node = nullptr);

// A split run's map node: frames that carry their depth (ReceivedFrameReader) through the cloud, `simplify`
// (or the configured windowed simplification when null) and the incremental map; labels come with the
// frames (no segmenter is loaded). `class_map`: the labels' scheme.
std::unique_ptr<Pipeline> MakeMapNodePipeline(const Config& config, std::unique_ptr<FrameReader> frames,
                                              const ClassMap& class_map,
                                              std::unique_ptr<SimplifyStage> simplify = nullptr);

}  // namespace semap::app
