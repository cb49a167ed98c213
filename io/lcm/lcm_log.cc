#include "io/lcm/lcm_log.h"

#include <lcm/lcm-cpp.hpp>

#include "engine/core/mesh_delta.h"
#include "io/lcm/lcm_codec.h"
#include "io/mesh/ply_off.h"

namespace semap::io {
namespace {

template <typename Msg>
Msg Decode(const lcm::LogEvent& event, const std::filesystem::path& path) {
  Msg msg;
  if (msg.decode(event.data, 0, event.datalen) < 0) {
    throw FileError(path, "undecodable message on channel " + event.channel + " (event " +
                              std::to_string(event.eventnum) + ")");
  }
  return msg;
}

}  // namespace

MeshLogReplay ReplayMeshLog(const std::filesystem::path& log_path, const std::string& channel_prefix) {
  if (!std::filesystem::is_regular_file(log_path)) throw FileError(log_path, "no such LCM log file");
  lcm::LogFile log(log_path.string(), "r");
  if (!log.good()) throw FileError(log_path, "cannot open as an LCM log");
  const std::string snapshot_channel = channel_prefix + "MESH_SNAPSHOT";
  const std::string delta_channel = channel_prefix + "MESH_DELTA";
  MeshLogReplay replay;
  MeshAccumulator acc;
  std::int64_t expected_sequence = -1;
  std::int64_t events = 0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    ++events;
    if (event->channel == snapshot_channel) {
      const auto msg = Decode<semap_lcm::mesh_snapshot_t>(*event, log_path);
      acc.Reset();
      acc.Apply(FromLcm(msg));
      ++replay.snapshots;
      replay.last_frame_id = msg.frame_id;
      expected_sequence = msg.sequence + 1;
    } else if (event->channel == delta_channel) {
      const auto msg = Decode<semap_lcm::mesh_delta_t>(*event, log_path);
      if (expected_sequence < 0) continue;  // no snapshot yet: a delta alone cannot be applied
      if (msg.sequence != expected_sequence) replay.sequence_gaps += msg.sequence - expected_sequence;
      acc.Apply(FromLcm(msg));
      ++replay.deltas;
      replay.last_frame_id = msg.frame_id;
      expected_sequence = msg.sequence + 1;
    } else {
      ++replay.other_events;
    }
  }
  if (events == 0 && std::filesystem::file_size(log_path) > 0) {
    throw FileError(log_path, "not an LCM log (no event found)");
  }
  replay.mesh = acc.ToMesh();
  return replay;
}

}  // namespace semap::io
