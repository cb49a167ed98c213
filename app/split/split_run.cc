#include "app/split/split_run.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <memory>

#include "app/run/engine_pipeline.h"
#include "app/split/lcm_link.h"

namespace semap::app {

StreamRunResult RunDepthNode(const Config& node_config, StreamRunRequest request, FrameShare share,
                             const std::string& node_name, const DepthFramePublisher::Send& send) {
  Config config = node_config;
  config.output.mesh_ply = config.output.mesh_off = false;  // no map here
  const std::int64_t frames = OpenStreamingSource(config, request.dataset)->size();
  const io::DepthFrameSender sender(config.depth_frames, config.split.run_id, DepthConfigFingerprint(config),
                                    node_name);
  DepthFramePublisher publisher(sender, config.input.first_frame, frames, send);
  spdlog::info("depth node {}: frames {} of every {} of {}, run {}", node_name, share.index, share.count,
               frames, config.split.run_id);
  const DepthNodeWiring wiring{&publisher, share};
  request.depth_node = &wiring;
  DropNoticeSink notices(&publisher);
  request.extra_sinks.push_back(&notices);
  request.lcm = RunOutputs::Lcm::kOff;  // no mesh to publish
  StreamRunResult result = StreamRun(config, request);
  const DepthFramePublisher::Counters c = publisher.counters();
  const double per_frame = c.frames > 0 ? 1.0 / static_cast<double>(c.frames) : 0.0;
  spdlog::info(
      "depth node {}: sent {} frames and {} drop notices in {} datagrams, {:.2f} MB ({:.0f} kB a "
      "frame), encoding {:.1f} ms a frame",
      node_name, c.frames, c.notices, c.datagrams, static_cast<double>(c.bytes) / 1e6,
      static_cast<double>(c.bytes) / 1e3 * per_frame, c.encode_ms * per_frame);
  return result;
}

StreamRunResult RunMapNode(const Config& config, StreamRunRequest request,
                           std::shared_ptr<ReceivedFrames> frames) {
  // A stop request (Ctrl-C) ends the wait for frames too.
  auto running = std::make_shared<std::atomic<Pipeline*>>(nullptr);
  request.on_running = [running, told = request.on_running](Pipeline* pipeline) {
    running->store(pipeline);
    if (told) told(pipeline);
  };
  request.received_frames = [frames, running] {
    return std::make_unique<ReceivedFrameReader>(frames, [running] {
      const Pipeline* p = running->load();
      return p != nullptr && p->StopRequested();
    });
  };
  StreamRunResult result = StreamRun(config, request);
  const ReceivedFrames::Counters c = frames->counters();
  spdlog::info(
      "depth frames: {} received whole, {} lost ({} announced by their node), {} late; {} parts ({} "
      "repeated, {} malformed, {} of other runs, {} refused); decoding {:.1f} ms a frame",
      c.frames, c.lost, c.parts.notices, c.late, c.parts.parts, c.parts.duplicates, c.parts.malformed,
      c.parts.foreign_run, c.parts.refused, c.frames > 0 ? c.decode_ms / static_cast<double>(c.frames) : 0.0);
  if (c.frames == 0) {
    spdlog::error("no depth frame of run {} arrived whole within {:g} s", config.split.run_id,
                  config.split.first_frame_timeout_s);
    result.outcome = StreamRunOutcome::kNothingMapped;
  }
  return result;
}

StreamRunResult RunDepthNodeOverLcm(const Config& config, StreamRunRequest request, FrameShare share,
                                    const std::string& node_name) {
  const std::string channel = DepthFrameChannel(config.lcm.channel_prefix);
  DepthFrameLcmPublisher lcm(config.lcm.url, channel);
  std::int64_t refused = 0;  // DepthFramePublisher serialises the calls
  spdlog::info("depth node {}: publishing on {} at {}", node_name, channel, config.lcm.url);
  StreamRunResult result =
      RunDepthNode(config, std::move(request), share, node_name,
                   [&](const io::EncodedMessage& d) { refused += lcm.Publish(d) ? 0 : 1; });
  if (refused > 0) spdlog::warn("depth node {}: LCM refused {} datagrams", node_name, refused);
  return result;
}

StreamRunResult RunMapNodeOverLcm(const Config& config, StreamRunRequest request) {
  // The time base of ReceivedFrameReader (SteadyClock): the LCM thread stamps each datagram on it.
  auto clock = std::make_shared<SteadyClock>();
  auto frames = std::make_shared<ReceivedFrames>(config.split, DepthConfigFingerprint(config), clock->NowS());
  const std::string channel = DepthFrameChannel(config.lcm.channel_prefix);
  DepthFrameLcmSubscriber subscriber(config.lcm.url, channel, [frames, clock](const void* data, size_t size) {
    frames->Add(data, size, clock->NowS());
  });
  spdlog::info("map node: depth frames of run {} from {} at {} (waiting up to {:g} s for the first)",
               config.split.run_id, channel, config.lcm.url, config.split.first_frame_timeout_s);
  return RunMapNode(config, std::move(request), frames);
}

}  // namespace semap::app
