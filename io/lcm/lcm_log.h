// LCM logs (as lcm-logger writes them) read and written without liblcm's log reader, which trusts every event
// header; and the mesh of a semap run rebuilt from a log or from a live subscription.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/mesh.h"
#include "io/lcm/mesh_blocks.h"

namespace semap::io {

// One event of an LCM log. On disk, big-endian: sync word 0xEDA1DA01, event number (int64), timestamp
// (int64, microseconds), channel length (int32), data length (int32), channel, data.
struct LcmLogEvent {
  std::int64_t eventnum = 0;
  std::int64_t timestamp_us = 0;
  std::string channel;
  std::vector<std::uint8_t> data;
};

// Reads a log event by event. Every header is checked against the file (sync word, channel length at most
// 256, data within the file): a damaged header is skipped by searching for the next sync word, and counted.
// Not thread-safe.
class LcmLogReader {
 public:
  // Throws FileError naming the path if it cannot be opened.
  explicit LcmLogReader(const std::filesystem::path& path);
  // The next event; nullopt at the end of the file.
  std::optional<LcmLogEvent> Next();
  std::int64_t damaged_bytes() const { return damaged_bytes_; }  // bytes skipped between events
  std::int64_t damaged_headers() const { return damaged_headers_; }
  // "" or what ended or interrupted the log ("event at byte N claims M bytes, the file has K", ...): the
  // first.
  const std::string& problem() const { return problem_; }

 private:
  bool ReadAt(std::int64_t pos, void* out, std::int64_t n);
  std::filesystem::path path_;
  std::ifstream in_;
  std::int64_t size_ = 0;
  std::int64_t pos_ = 0;
  std::int64_t damaged_bytes_ = 0;
  std::int64_t damaged_headers_ = 0;
  std::string problem_;
};

// Appends one event to an LCM log stream (as lcm-logger writes it).
void WriteLcmLogEvent(std::ostream& out, const LcmLogEvent& event);

struct MeshReplayOptions {
  // Channels <prefix>MESH_BLOCK and <prefix>MESH_END.
  std::string channel_prefix = "SEMAP_";
  // >= 0: ignore the events of the first `join_after_s` seconds of the log, as a subscriber started late
  // would, and report when it caught up with one that listened from the start.
  double join_after_s = -1.0;
};

struct MeshReplay {
  Mesh mesh;  // every block held, at its latest complete version
  MeshBlockAssembler::Counters blocks;
  std::vector<std::string> missing;  // blocks still lacking (MeshBlockAssembler::Missing)
  bool index_complete = false;       // every block of the run's latest index is held
  std::int64_t events = 0;           // events read (live: messages received)
  std::int64_t mesh_events = 0;      // block and index messages accepted
  std::int64_t skipped = 0;          // mesh messages skipped as invalid (bad counts, NaN, unknown vertex...)
  std::vector<std::string> skipped_reasons;  // the first few, naming the event and the problem
  std::int64_t other_events = 0;             // events on other channels
  std::int64_t mesh_bytes = 0;               // bytes of mesh block and index messages
  std::int64_t largest_message = 0;          // bytes of the largest event on any channel
  std::int64_t damaged_bytes = 0;            // log bytes skipped between events (damaged headers)
  std::string log_problem;                   // LcmLogReader::problem
  double duration_s = 0.0;                   // first to last event
  double converged_after_s = -1.0;  // with join_after_s: seconds after joining until the late subscriber held
                                    // every block the early one held (-1: never)
};

// Rebuilds the mesh of a semap run from an lcm-logger log; damaged events and invalid messages are skipped
// and counted. Throws FileError naming the path if the file is missing, empty, not an LCM log, or holds no
// valid mesh message on the prefix's channels (naming the channels it does hold).
MeshReplay ReplayMeshLog(const std::filesystem::path& log_path, const MeshReplayOptions& options = {});

// Subscribes to `url` and rebuilds the mesh until the run's last message arrives, every block of its closing
// index is held, or `seconds` pass. Throws LcmError naming the URL if it cannot be opened.
MeshReplay ReceiveMeshLive(const std::string& url, double seconds,
                           const std::string& channel_prefix = "SEMAP_");

}  // namespace semap::io
