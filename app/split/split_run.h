// The two halves of a split run, each a StreamRun: a depth node publishes its share of a sequence's frames'
// depth; a map node builds the map from whatever the depth nodes of its run publish, and writes the outputs
// `semap run` writes. The transport is the caller's (LCM: the *OverLcm functions; a test: memory).
#pragma once

#include <memory>
#include <string>

#include "app/config/config.h"
#include "app/run/stream_run.h"
#include "app/split/depth_node.h"
#include "app/split/received_frames.h"

namespace semap::app {

// The frames of `share` through depth and labels, each frame's result encoded as the run split.run_id's
// node `node_name` and handed to `send` (from the depth workers, one call at a time); no map and no mesh
// files. Logs what it sent. Throws what StreamRun throws.
StreamRunResult RunDepthNode(const Config& config, StreamRunRequest request, FrameShare share,
                             const std::string& node_name, const DepthFramePublisher::Send& send);

// The frames of `frames` (fed by the caller's transport) through the cloud, the simplification and the map,
// into config.output (and the mesh over LCM when lcm.enabled). Logs what it received, lost and refused.
// kNothingMapped when no frame arrived whole.
StreamRunResult RunMapNode(const Config& config, StreamRunRequest request,
                           std::shared_ptr<ReceivedFrames> frames);

// `semap run DATASET --publish-depth`: RunDepthNode publishing on lcm.url, channel
// <lcm.channel_prefix>DEPTH_FRAME. Throws io::LcmError when the URL cannot be opened.
StreamRunResult RunDepthNodeOverLcm(const Config& config, StreamRunRequest request, FrameShare share,
                                    const std::string& node_name);

// `semap map`: RunMapNode on the depth frames received on lcm.url, channel <lcm.channel_prefix>DEPTH_FRAME,
// waiting up to split.first_frame_timeout_s for the first. Throws io::LcmError when the URL cannot be opened.
StreamRunResult RunMapNodeOverLcm(const Config& config, StreamRunRequest request);

}  // namespace semap::app
