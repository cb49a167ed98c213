#include "io/lcm/lcm_log.h"

#include <algorithm>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <map>

#include "io/file_error.h"
#include "io/lcm/lcm_publisher.h"

namespace semap::io {
namespace {

constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::int64_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;
constexpr std::int32_t kMaxChannelBytes = 256;  // LCM's own limit is 63
constexpr size_t kMaxReasons = 5;

std::uint64_t BigEndian(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

void PutBigEndian(std::ostream& out, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) out.put(static_cast<char>((v >> (8 * i)) & 0xff));
}

// Feeds mesh messages to an assembler, counting what it skips (shared by the log replay and the live
// subscription).
class MeshMessageSink {
 public:
  MeshMessageSink(const std::string& prefix, MeshReplay* out)
      : block_channel_(prefix + "MESH_BLOCK"), end_channel_(prefix + "MESH_END"), out_(out) {}

  // Returns whether the event was a valid mesh message (fed to the assembler).
  bool Feed(const std::string& channel, const void* data, size_t size, const std::string& where,
            MeshBlockAssembler* assembler) {
    ++out_->events;
    out_->largest_message = std::max<std::int64_t>(out_->largest_message, static_cast<std::int64_t>(size));
    const bool block = channel == block_channel_;
    if (!block && channel != end_channel_) {
      ++out_->other_events;
      ++other_channels_[channel];
      return false;
    }
    out_->mesh_bytes += static_cast<std::int64_t>(size);
    std::string error;
    bool ok = false;
    if (block) {
      if (auto msg = DecodeMeshBlock(data, size, &error)) {
        assembler->Add(*msg);
        ok = true;
      }
    } else if (auto msg = DecodeMeshEnd(data, size, &error)) {
      assembler->Add(*msg);
      ok = true;
    }
    if (ok) {
      ++out_->mesh_events;
    } else {
      ++out_->skipped;
      if (out_->skipped_reasons.size() < kMaxReasons)
        out_->skipped_reasons.push_back(where + " on " + channel + ": " + error);
    }
    return ok;
  }

  std::string OtherChannels() const {
    std::string s;
    for (const auto& [c, n] : other_channels_)
      s += (s.empty() ? "" : ", ") + c + " (" + std::to_string(n) + ")";
    return s.empty() ? "none" : s;
  }

 private:
  std::string block_channel_, end_channel_;
  MeshReplay* out_;
  std::map<std::string, std::int64_t> other_channels_;
};

void Finish(const MeshBlockAssembler& assembler, MeshReplay* out) {
  out->mesh = assembler.ToMesh();
  out->blocks = assembler.counters();
  out->missing = assembler.Missing();
  out->index_complete = assembler.Complete();
}

}  // namespace

LcmLogReader::LcmLogReader(const std::filesystem::path& path) : path_(path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw FileError(path, "no such LCM log file");
  in_.open(path, std::ios::binary);
  if (!in_) throw FileError(path, "cannot open for reading");
  size_ = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
}

bool LcmLogReader::ReadAt(std::int64_t pos, void* out, std::int64_t n) {
  if (pos < 0 || n < 0 || pos + n > size_) return false;
  in_.clear();
  in_.seekg(pos);
  in_.read(static_cast<char*>(out), n);
  return static_cast<std::int64_t>(in_.gcount()) == n;
}

std::optional<LcmLogEvent> LcmLogReader::Next() {
  while (pos_ + kHeaderBytes <= size_) {
    std::uint8_t h[kHeaderBytes];
    if (!ReadAt(pos_, h, kHeaderBytes)) break;
    const auto sync = static_cast<std::uint32_t>(BigEndian(h, 4));
    const auto channel_len = static_cast<std::int32_t>(BigEndian(h + 20, 4));
    const auto data_len = static_cast<std::int32_t>(BigEndian(h + 24, 4));
    std::string bad;
    if (sync != kSyncWord) {
      bad = "no sync word";
    } else if (channel_len <= 0 || channel_len > kMaxChannelBytes) {
      bad = "channel length " + std::to_string(channel_len);
    } else if (data_len < 0 || pos_ + kHeaderBytes + channel_len + std::int64_t(data_len) > size_) {
      bad = "data length " + std::to_string(data_len) + " (the file has " +
            std::to_string(size_ - pos_ - kHeaderBytes - channel_len) + " bytes left)";
    }
    if (bad.empty()) {
      LcmLogEvent e;
      e.eventnum = static_cast<std::int64_t>(BigEndian(h + 4, 8));
      e.timestamp_us = static_cast<std::int64_t>(BigEndian(h + 12, 8));
      e.channel.resize(static_cast<size_t>(channel_len));
      e.data.resize(static_cast<size_t>(data_len));
      if (ReadAt(pos_ + kHeaderBytes, e.channel.data(), channel_len) &&
          ReadAt(pos_ + kHeaderBytes + channel_len, e.data.data(), data_len)) {
        pos_ += kHeaderBytes + channel_len + data_len;
        return e;
      }
      bad = "unreadable";
    }
    if (problem_.empty()) problem_ = "damaged event header at byte " + std::to_string(pos_) + ": " + bad;
    ++damaged_headers_;
    // Search for the next sync word after this one, as liblcm does, but within the file's bounds.
    std::int64_t next = pos_ + 1;
    std::vector<std::uint8_t> chunk(1 << 16);
    bool found = false;
    while (!found && next + 4 <= size_) {
      const std::int64_t n = std::min<std::int64_t>(static_cast<std::int64_t>(chunk.size()), size_ - next);
      if (!ReadAt(next, chunk.data(), n)) break;
      for (std::int64_t i = 0; i + 4 <= n; ++i) {
        if (BigEndian(chunk.data() + i, 4) == kSyncWord) {
          next += i;
          found = true;
          break;
        }
      }
      if (!found) next += std::max<std::int64_t>(1, n - 3);
    }
    if (!found) next = size_;
    damaged_bytes_ += next - pos_;
    pos_ = next;
  }
  if (pos_ < size_) {
    if (problem_.empty())
      problem_ = "truncated: " + std::to_string(size_ - pos_) + " bytes at the end are no event";
    damaged_bytes_ += size_ - pos_;
    pos_ = size_;
  }
  return std::nullopt;
}

void WriteLcmLogEvent(std::ostream& out, const LcmLogEvent& e) {
  PutBigEndian(out, kSyncWord, 4);
  PutBigEndian(out, static_cast<std::uint64_t>(e.eventnum), 8);
  PutBigEndian(out, static_cast<std::uint64_t>(e.timestamp_us), 8);
  PutBigEndian(out, e.channel.size(), 4);
  PutBigEndian(out, e.data.size(), 4);
  out.write(e.channel.data(), static_cast<std::streamsize>(e.channel.size()));
  out.write(reinterpret_cast<const char*>(e.data.data()), static_cast<std::streamsize>(e.data.size()));
}

MeshReplay ReplayMeshLog(const std::filesystem::path& log_path, const MeshReplayOptions& options) {
  LcmLogReader reader(log_path);
  MeshReplay out;
  MeshMessageSink sink(options.channel_prefix, &out);
  MeshBlockAssembler assembler;  // the subscriber (joining late with join_after_s)
  MeshBlockAssembler early;      // with join_after_s: one that listened from the start
  MeshReplay early_counts;       // not reported
  MeshMessageSink early_sink(options.channel_prefix, &early_counts);
  std::int64_t first_us = 0, last_us = 0;
  bool converged = false;
  while (auto e = reader.Next()) {
    if (out.events == 0) first_us = e->timestamp_us;
    last_us = e->timestamp_us;
    const double t =
        1e-6 * (static_cast<double>(e->timestamp_us) - static_cast<double>(first_us));  // any int64
    const std::string where = "event " + std::to_string(e->eventnum);
    if (options.join_after_s < 0) {
      sink.Feed(e->channel, e->data.data(), e->data.size(), where, &assembler);
      continue;
    }
    // Both subscribers see the event (the early one always, the late one once joined); counted once.
    early_sink.Feed(e->channel, e->data.data(), e->data.size(), where, &early);
    if (t < options.join_after_s) {
      ++out.events;
      continue;
    }
    if (sink.Feed(e->channel, e->data.data(), e->data.size(), where, &assembler) && !converged &&
        assembler.Holds(early)) {
      converged = true;
      out.converged_after_s = t - options.join_after_s;
    }
  }
  out.duration_s = 1e-6 * (static_cast<double>(last_us) - static_cast<double>(first_us));
  out.damaged_bytes = reader.damaged_bytes();
  out.log_problem = reader.problem();
  if (out.events == 0) {
    throw FileError(log_path, reader.damaged_bytes() > 0 ? "not an LCM log (no event found)"
                                                         : "empty LCM log (no event)");
  }
  if (out.mesh_events == 0) {
    std::string why = "no valid mesh message on " + options.channel_prefix + "MESH_BLOCK / " +
                      options.channel_prefix + "MESH_END among " + std::to_string(out.events) +
                      " events (other channels: " + sink.OtherChannels() + ")";
    if (!out.skipped_reasons.empty()) why += "; skipped: " + out.skipped_reasons.front();
    throw FileError(log_path, why);
  }
  Finish(assembler, &out);
  return out;
}

MeshReplay ReceiveMeshLive(const std::string& url, double seconds, const std::string& channel_prefix) {
  lcm::LCM lcm(url);
  if (!lcm.good()) throw LcmError("cannot open LCM URL '" + url + "'");
  MeshReplay out;
  MeshMessageSink sink(channel_prefix, &out);
  MeshBlockAssembler assembler;
  struct Context {
    MeshMessageSink* sink;
    MeshBlockAssembler* assembler;
  } context{&sink, &assembler};
  const auto handler = [](const lcm::ReceiveBuffer* rbuf, const std::string& channel, Context* c) {
    c->sink->Feed(channel, rbuf->data, rbuf->data_size, "message", c->assembler);
  };
  lcm.subscribeFunction<Context*>(channel_prefix + "MESH_BLOCK", handler, &context);
  lcm.subscribeFunction<Context*>(channel_prefix + "MESH_END", handler, &context);
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (lcm.handleTimeout(static_cast<int>(std::clamp<std::int64_t>(left.count(), 1, 200))) < 0) break;
    const auto& c = assembler.counters();
    if (c.run_ended || (c.closing_seen && assembler.Complete())) break;
  }
  out.duration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Finish(assembler, &out);
  return out;
}

}  // namespace semap::io
