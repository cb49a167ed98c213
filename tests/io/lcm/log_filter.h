// Test helper: a filtered copy of an LCM log (lost messages, a subscriber that started late).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "io/lcm/lcm_log.h"

namespace semap::test {

inline bool IsMeshEvent(const io::LcmLogEvent& e) {
  return e.channel.ends_with("MESH_BLOCK") || e.channel.ends_with("MESH_END");
}

// Copies `in` to `out` keeping the events for which keep(index, event) holds; returns the events dropped.
template <typename Keep>
std::int64_t FilterLog(const std::filesystem::path& in, const std::filesystem::path& out, Keep keep) {
  io::LcmLogReader reader(in);
  std::ofstream os(out, std::ios::binary);
  std::int64_t index = 0, dropped = 0;
  while (auto e = reader.Next()) {
    if (keep(index++, *e)) {
      io::WriteLcmLogEvent(os, *e);
    } else {
      ++dropped;
    }
  }
  return dropped;
}

// Events in the log.
inline std::int64_t CountEvents(const std::filesystem::path& log) {
  io::LcmLogReader reader(log);
  std::int64_t n = 0;
  while (reader.Next()) ++n;
  return n;
}

}  // namespace semap::test
